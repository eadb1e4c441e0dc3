// Importing logs on the command line (issue 13): the four foreign layouts through --map/--unit/
// --time and through --mapping give the metrics of the same data in kfw's format; inspect shows
// each file; bad files give one line with the file and line; the renamed real log with its gyro in
// rad/s gives the original RMSE.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/cli_runner.h"
#include "common/import_files.h"
#include "data/csv.h"

namespace {

namespace fs = std::filesystem;
using kfw::testing::cli;
using kfw::testing::close12;
using Json = nlohmann::json;

class ImportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::path(::testing::TempDir()) /
          ("kfw_import_cli_" +
           std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    if (!kfw::testing::make_import_files(dir, 6000, files)) GTEST_SKIP() << "no real log";
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }

  // The metrics of `broad_imu` on a file with the given import options.
  Json metrics(const std::string& file, const std::string& options) {
    const auto o = cli("run broad_imu --data " + file + " " + options, "2>/dev/null");
    EXPECT_EQ(o.code, 0) << options << "\n" << o.text;
    auto j = Json::parse(o.text, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << o.text;
    return j;
  }

  void expect_same_metrics(const Json& got, const Json& want, const std::string& what) {
    ASSERT_TRUE(want.contains("rmse")) << want.dump();
    for (auto it = want.begin(); it != want.end(); ++it) {
      if (!it->is_number()) continue;
      ASSERT_TRUE(got.contains(it.key())) << what << ": no " << it.key();
      EXPECT_TRUE(close12(got[it.key()].get<double>(), it->get<double>()))
          << what << ": " << it.key() << " " << got[it.key()] << " vs " << *it;
    }
  }

  void write(const std::string& name, const std::string& text) {
    std::ofstream(path(name), std::ios::binary) << text;
  }

  fs::path dir;
  kfw::testing::ImportFiles files;
};

struct Layout {
  const char* name;
  std::string kfw::testing::ImportFiles::*file;
  const char* options;  // --map/--unit/--time
  const char* mapping;  // the same as a mapping block
};

const Layout kLayouts[] = {
    {"units", &kfw::testing::ImportFiles::units,
     "--time time_ms:ms --map gyro=omega_rads --unit gyro=rad/s --map angle=acc_roll_deg "
     "--map truth=ref_roll_deg",
     R"({"t": {"column": "time_ms", "unit": "ms"}, "gyro": {"column": "omega_rads", "unit":
        "rad/s"}, "angle": "acc_roll_deg", "truth": "ref_roll_deg"})"},
    {"german", &kfw::testing::ImportFiles::german,
     "--time Zeit --map gyro=Drehrate --unit gyro=rad/s --map angle=Winkel --map truth=Referenz",
     R"({"t": "Zeit", "gyro": {"column": "Drehrate", "unit": "rad/s"}, "angle": "Winkel",
        "truth": "Referenz"})"},
    {"tabs", &kfw::testing::ImportFiles::tabs,
     "--sep tab --time time --map gyro=gyro_dps --map angle=roll_deg --map truth=truth_deg",
     R"({"t": "time", "gyro": "gyro_dps", "angle": "roll_deg", "truth": "truth_deg"})"},
    {"iso", &kfw::testing::ImportFiles::iso, "--time timestamp:iso",
     R"({"mapping": {"t": {"column": "timestamp", "unit": "iso"}}})"},
};

TEST_F(ImportCli, EachLayoutGivesTheMetricsOfTheKfwFile) {
  const Json want = metrics(files.reference, "");
  for (const auto& l : kLayouts) {
    const std::string file = files.*(l.file);
    const Json by_options = metrics(file, l.options);
    expect_same_metrics(by_options, want, std::string(l.name) + " --map");
    write(std::string(l.name) + ".json", l.mapping);
    const Json by_file = metrics(file, "--mapping " + path(std::string(l.name) + ".json"));
    EXPECT_EQ(by_file, by_options) << l.name << ": --mapping and --map differ";
  }
}

TEST_F(ImportCli, OptionsOverrideTheMappingFileKeyByKey) {
  // The file maps gyro to a wrong column; --map fixes only that role's column, its unit stays.
  write("m.json", R"({"gyro": {"column": "acc_roll_deg", "unit": "rad/s"}, "angle":
                      "acc_roll_deg", "t": {"column": "time_ms", "unit": "ms"},
                      "truth": "ref_roll_deg"})");
  const Json want = metrics(files.reference, "");
  expect_same_metrics(
      metrics(files.units, "--mapping " + path("m.json") + " --map gyro=omega_rads"), want,
      "override");
}

TEST_F(ImportCli, InspectShowsEachFile) {
  struct Want {
    std::string file, separator;
    bool decimal_comma;
    Json mapping;
  };
  const Want wants[] = {
      {files.units, "comma", false,
       Json::parse(R"({"angle": {"column": "acc_roll_deg", "unit": "deg"}, "gyro": {"column":
         "omega_rads", "unit": "rad/s"}, "t": {"column": "time_ms", "unit": "ms"}, "truth":
         {"column": "ref_roll_deg", "unit": "deg"}})")},
      {files.german, "semicolon", true,
       Json::parse(R"({"angle": "Winkel", "gyro": "Drehrate", "t": "Zeit"})")},
      {files.tabs, "tab", false,
       Json::parse(R"({"angle": {"column": "roll_deg", "unit": "deg"}, "gyro": {"column":
         "gyro_dps", "unit": "deg/s"}, "t": "time", "truth": {"column": "truth_deg", "unit":
         "deg"}})")},
      {files.iso, "comma", false,
       Json::parse(R"({"angle": "angle", "gyro": "gyro", "t": {"column": "timestamp", "unit":
         "iso"}, "truth": "truth"})")},
  };
  for (const auto& w : wants) {
    const auto o = cli("inspect " + w.file + " broad_imu --json", "2>/dev/null");
    ASSERT_EQ(o.code, 0) << o.text;
    const Json j = Json::parse(o.text);
    EXPECT_EQ(j["separator"], w.separator) << w.file;
    EXPECT_EQ(j["decimal_comma"], w.decimal_comma) << w.file;
    EXPECT_EQ(j["rows"], files.rows) << w.file;
    EXPECT_EQ(j["mapping"], w.mapping) << w.file;
    EXPECT_EQ(j["missing"], Json::array()) << w.file;
    // 6000 rows at 3.5 ms: 20.9965 s, 285.714 Hz.
    EXPECT_NEAR(j["time"]["span_s"].get<double>(), 5999 * 0.0035, 1e-9) << w.file;
    EXPECT_NEAR(j["time"]["rate_hz"].get<double>(), 1.0 / 0.0035, 1e-6) << w.file;
  }
  const Json iso = Json::parse(cli("inspect " + files.iso + " --json", "2>/dev/null").text);
  EXPECT_EQ(iso["time"]["origin"], "2024-05-01T10:00:00.000000000Z");
  const auto text = cli("inspect " + files.german + " helicopter");
  EXPECT_EQ(text.code, 0);
  EXPECT_NE(text.text.find("separator: semicolon (decimal comma)"), std::string::npos) << text.text;
  EXPECT_NE(text.text.find("rows: 6000"), std::string::npos) << text.text;
  EXPECT_NE(text.text.find("--time Zeit --map angle=Winkel --map gyro=Drehrate"), std::string::npos)
      << text.text;
}

TEST_F(ImportCli, BadFilesGiveOneLineWithFileAndLine) {
  write("empty.csv", "");
  write("header.csv", "time_ms,omega_rads,acc_roll_deg\n");
  write("novalue.csv", "t,gyro,angle\n0,1,\n0.01,2,\n");
  write("binary.csv", std::string("t,gyro\n0,1\n\x7f"
                                  "ELF\x00\x01",
                                  17));
  write("decreasing.csv", "t,gyro,angle\n0,1,2\n0.02,1,2\n0.01,1,2\n");
  const std::pair<std::string, std::string> cases[] = {
      {"empty.csv", "empty.csv: empty file"},
      {"header.csv", "header.csv: no data rows after the header"},
      {"novalue.csv", "novalue.csv: column 'angle' has no value"},
      {"binary.csv", "binary.csv:3: not a text file (NUL byte)"},
      {"decreasing.csv", "decreasing.csv:4:1: time is not increasing (t = 0.01 after 0.02)"},
  };
  for (const auto& [name, fragment] : cases) {
    const auto o = cli("run helicopter --data " + path(name));
    EXPECT_EQ(o.code, 2) << name << ": " << o.text;
    EXPECT_NE(o.text.find(fragment), std::string::npos) << o.text;
    EXPECT_EQ(std::count(o.text.begin(), o.text.end(), '\n'), 1) << o.text;
  }
  // A header that needs a mapping: the message says which.
  const auto o = cli("run helicopter --data " + files.units);
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.text.find("missing required column 't'"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("--time time_ms:ms"), std::string::npos) << o.text;
  const auto role = cli("run helicopter --data " + files.units + " --map gyr=omega_rads");
  EXPECT_EQ(role.code, 2);
  EXPECT_NE(role.text.find("--map: unknown role 'gyr'"), std::string::npos) << role.text;
  const auto unit = cli("run helicopter --data " + files.units + " --unit gyro=furlong");
  EXPECT_EQ(unit.code, 2);
  EXPECT_NE(unit.text.find("unknown unit 'furlong'"), std::string::npos) << unit.text;
}

TEST_F(ImportCli, RenamedRealLogWithGyroInRadPerSecondGivesTheSameRmse) {
  auto log = kfw::read_csv(kfw::testing::kRealLog);
  ASSERT_TRUE(log.ok()) << log.error();
  const double rad = 3.14159265358979323846 / 180.0;
  std::ofstream out(path("renamed.csv"));
  out << "stamp_s,gyro_x_rads,acc_roll,mocap_roll\n";
  for (std::size_t i = 0; i < log->rows(); ++i) {
    out << kfw::testing::g17(log->col("t")[i]) << ','
        << kfw::testing::g17(log->col("gyro")[i] * rad) << ','
        << kfw::testing::g17(log->col("angle")[i]) << ',' << kfw::testing::g17(log->col("truth")[i])
        << '\n';
  }
  out.close();
  const auto original = cli("run broad_imu", "2>/dev/null");
  ASSERT_EQ(original.code, 0) << original.text;
  const Json want = Json::parse(original.text);
  const Json got = metrics(path("renamed.csv"),
                           "--time stamp_s --map gyro=gyro_x_rads --unit gyro=rad/s "
                           "--map angle=acc_roll --map truth=mocap_roll");
  EXPECT_TRUE(close12(got["rmse"].get<double>(), want["rmse"].get<double>()))
      << got["rmse"] << " vs " << want["rmse"];
  expect_same_metrics(got, want, "renamed");
}

}  // namespace
