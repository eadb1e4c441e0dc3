// How a file is read, on the command line (issue 13): the separator and the header row stored in
// a mapping file or a preset's mapping ("sep", "header") are used, and --sep / --header override
// them key by key; a file without a header loads by column position (col1, col2, ...), gives the
// kfw file's metrics, and inspect says "no header"; a text cell in such a file is named by
// FILE:LINE:COL.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/cli_runner.h"
#include "common/import_files.h"

namespace {

namespace fs = std::filesystem;
using kfw::testing::cli;
using kfw::testing::close12;
using Json = nlohmann::json;

constexpr const char* kByPosition = "--time col1 --map gyro=col2 --map angle=col3 --map truth=col4";

class ImportFormatCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::path(::testing::TempDir()) /
          ("kfw_import_format_cli_" +
           std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    if (!kfw::testing::make_import_files(dir, 3000, files)) GTEST_SKIP() << "no real log";
    // The kfw file without its header row.
    std::ifstream in(files.reference);
    std::string line, body;
    std::getline(in, line);
    while (std::getline(in, line))
      body += line + "\n";
    write("nohead.csv", body);
    want = run(files.reference, "");
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  void write(const std::string& name, const std::string& text) {
    std::ofstream(path(name), std::ios::binary) << text;
  }

  Json run(const std::string& file, const std::string& options, const std::string& preset = "") {
    const auto o = cli("run " + (preset.empty() ? std::string("broad_imu") : preset) + " --data " +
                           file + " " + options,
                       "2>/dev/null");
    EXPECT_EQ(o.code, 0) << options << "\n" << o.text;
    auto j = Json::parse(o.text, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << o.text;
    return j;
  }

  void expect_want(const Json& got, const std::string& what) {
    ASSERT_TRUE(want.contains("rmse")) << want.dump();
    for (auto it = want.begin(); it != want.end(); ++it) {
      if (!it->is_number()) continue;
      ASSERT_TRUE(got.contains(it.key())) << what << ": no " << it.key();
      EXPECT_TRUE(close12(got[it.key()].get<double>(), it->get<double>()))
          << what << ": " << it.key() << " " << got[it.key()] << " vs " << *it;
    }
  }

  fs::path dir;
  kfw::testing::ImportFiles files;
  Json want;
};

TEST_F(ImportFormatCli, TheMappingsSeparatorIsUsedAndSepOverridesIt) {
  const std::string roles =
      R"("t": "time", "gyro": "gyro_dps", "angle": "roll_deg", "truth": "truth_deg")";
  write("tab.json", R"({"sep": "tab", )" + roles + "}");
  write("comma.json", R"({"mapping": {"sep": "comma", )" + roles + "}}");
  expect_want(run(files.tabs, "--mapping " + path("tab.json")), "sep tab");
  // Read as comma-separated the tab file has one column: the stored separator is what was used.
  const auto wrong = cli("run broad_imu --data " + files.tabs + " --mapping " + path("comma.json"));
  EXPECT_EQ(wrong.code, 2) << wrong.text;
  EXPECT_NE(wrong.text.find(files.tabs + ": mapped column"), std::string::npos) << wrong.text;
  // --sep replaces only the separator; the file's roles stay.
  expect_want(run(files.tabs, "--mapping " + path("comma.json") + " --sep tab"), "--sep over");
  // The same through a preset's mapping block.
  ASSERT_EQ(cli("preset broad_imu --out " + path("p.json")).code, 0);
  Json p = Json::parse(std::ifstream(path("p.json")));
  p["mapping"] = Json::parse("{" + std::string(R"("sep": "comma", )") + roles + "}");
  std::ofstream(path("p.json")) << p.dump(2);
  EXPECT_EQ(cli("run " + path("p.json") + " --data " + files.tabs).code, 2);
  expect_want(run(files.tabs, "--sep tab", path("p.json")), "preset + --sep");
  const auto bad = cli("run broad_imu --data " + files.tabs + " --sep pipe");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.text.find("--sep: unknown separator 'pipe'"), std::string::npos) << bad.text;
}

TEST_F(ImportFormatCli, AHeaderlessFileLoadsByColumnPosition) {
  expect_want(run(path("nohead.csv"), kByPosition), "--map by position");
  write("nohead.json", R"({"header": "none", "t": "col1", "gyro": "col2", "angle": "col3",
                           "truth": "col4"})");
  expect_want(run(path("nohead.csv"), "--mapping " + path("nohead.json")), "mapping file");
  // Told that the first row is the header, the file has no col2: an error naming it.
  const auto first =
      cli("run broad_imu --data " + path("nohead.csv") + " --header first " + kByPosition);
  EXPECT_EQ(first.code, 2) << first.text;
  EXPECT_NE(first.text.find(path("nohead.csv") + ":1:"), std::string::npos) << first.text;
  // Told that a file with a header has none: its names are a row of text, named by line and column.
  const auto none =
      cli("run broad_imu --data " + files.reference + " --header none " + kByPosition);
  EXPECT_EQ(none.code, 2) << none.text;
  EXPECT_NE(none.text.find(files.reference + ":1:1: column 'col1': 't' is not a number"),
            std::string::npos)
      << none.text;
  EXPECT_EQ(std::count(none.text.begin(), none.text.end(), '\n'), 1) << none.text;
  const auto bad = cli("run broad_imu --data " + path("nohead.csv") + " --header yes");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.text.find("--header: unknown header 'yes'"), std::string::npos) << bad.text;
}

TEST_F(ImportFormatCli, ATextCellInAHeaderlessFileIsNamedByLineAndColumn) {
  write("bad.csv", "0,1,2,2\n0.01,1,2,2\n0.02,1,x,2\n0.03,1,2,2\n");
  const auto o = cli("run broad_imu --data " + path("bad.csv") + " " + kByPosition);
  EXPECT_EQ(o.code, 2) << o.text;
  EXPECT_NE(o.text.find(path("bad.csv") + ":3:8: "), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("'x' is not a number"), std::string::npos) << o.text;
  EXPECT_EQ(std::count(o.text.begin(), o.text.end(), '\n'), 1) << o.text;
}

TEST_F(ImportFormatCli, InspectSaysNoHeader) {
  const auto o = cli("inspect " + path("nohead.csv") + " --json", "2>/dev/null");
  ASSERT_EQ(o.code, 0) << o.text;
  const Json j = Json::parse(o.text);
  EXPECT_EQ(j["header"], "none");
  EXPECT_EQ(j["header_line"], 0);
  EXPECT_EQ(j["rows"], files.rows);
  ASSERT_EQ(j["columns"].size(), 4u);
  EXPECT_EQ(j["columns"][0]["name"], "col1");
  EXPECT_EQ(j["columns"][3]["name"], "col4");
  EXPECT_EQ(j["time"]["column"], "col1");  // the increasing first column
  EXPECT_NEAR(j["time"]["rate_hz"].get<double>(), 1.0 / 0.0035, 1e-6);
  const auto text = cli("inspect " + path("nohead.csv"));
  EXPECT_NE(text.text.find("no header: columns named by position, col1 .. col4"), std::string::npos)
      << text.text;
  // Forced: the first row names the columns.
  write("numbers.csv", "1,2\n3,4\n5,6\n");
  const Json first =
      Json::parse(cli("inspect " + path("numbers.csv") + " --header first --json").text);
  EXPECT_EQ(first["header"], "first");
  EXPECT_EQ(first["rows"], 2);
  EXPECT_EQ(first["columns"][1]["name"], "2");
  // With a preset: the mapping to give, the format included.
  const Json heli = Json::parse(
      cli("inspect " + path("nohead.csv") + " broad_imu --sep comma --json", "2>/dev/null").text);
  EXPECT_EQ(heli["mapping"]["sep"], "comma");
  EXPECT_EQ(heli["mapping"]["t"], "col1");
  EXPECT_EQ(heli["missing"], Json::parse(R"(["gyro", "angle"])"));
  // The tab file inspected as comma-separated: one column.
  const Json comma = Json::parse(cli("inspect " + files.tabs + " --sep comma --json").text);
  EXPECT_EQ(comma["separator"], "comma");
  EXPECT_EQ(comma["columns"].size(), 1u);
}

// The acceptance's "inspect output for each" in text form (the JSON form: ImportCli.InspectShows
// EachFile): separator, header line, rows, time column, rate and a complete mapping.
TEST_F(ImportFormatCli, InspectTextForEachLayout) {
  struct Want {
    std::string file, separator, time;
  };
  const Want wants[] = {
      {files.units, "separator: comma\n", "time: column 'time_ms' (ms)"},
      {files.german, "separator: semicolon (decimal comma)\n", "time: column 'Zeit' (s)"},
      {files.tabs, "separator: tab\n", "time: column 'time' (s)"},
      {files.iso, "separator: comma\n", "time: column 'timestamp' (iso)"},
  };
  for (const auto& w : wants) {
    const auto o = cli("inspect " + w.file + " broad_imu");
    ASSERT_EQ(o.code, 0) << o.text;
    for (const std::string& part :
         {w.separator, "rows: " + std::to_string(files.rows) + " (header on line ", w.time,
          std::string("rate: 285.714 Hz"), std::string("mapping for broad_imu: --time "),
          std::string("complete: every required role has a column")}) {
      EXPECT_NE(o.text.find(part), std::string::npos) << w.file << ": " << part << "\n" << o.text;
    }
  }
}

}  // namespace

namespace {
// One time sample: no step, so no rate — said in words and left out of the JSON, never a NaN.
TEST(ImportInspectCli, OneRowHasNoRateAndNoNaN) {
  const auto file = fs::path(::testing::TempDir()) / "kfw_inspect_one_row.csv";
  std::ofstream(file) << "t,gyro\n0.5,2\n";
  const auto text = cli("inspect " + file.string());
  EXPECT_EQ(text.code, 0) << text.text;
  EXPECT_NE(text.text.find("rate: undefined (fewer than two time samples)"), std::string::npos)
      << text.text;
  EXPECT_EQ(text.text.find("nan"), std::string::npos) << text.text;
  const auto json = cli("inspect " + file.string() + " --json", "2>/dev/null");
  ASSERT_EQ(json.code, 0) << json.text;
  const auto j = Json::parse(json.text);
  EXPECT_FALSE(j["time"].contains("median_step_s"));
  EXPECT_FALSE(j["time"].contains("rate_hz"));
  EXPECT_EQ(j["time"]["rate_undefined"], "fewer than two time samples");
}
}  // namespace
