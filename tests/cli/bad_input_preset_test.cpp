// The bad-input matrix, preset JSON (issue 16): `kfw-cli run PRESET --out --metrics` on every class
// of bad preset. Each case: exit 2 before any work, one line naming FILE:LINE:COL or the dotted
// key, nothing written (common/bad_input.h).
#include <chrono>

#include "common/bad_input.h"

namespace kfw {
namespace {

using testing::cli;

class BadPreset : public testing::BadInput {
 protected:
  // The shipped helicopter preset with `from` replaced by `to` (the first occurrence).
  std::string edited(const std::string& name, const std::string& from, const std::string& to) {
    std::string p = source("presets/helicopter.json");
    const auto at = p.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) p.replace(at, from.size(), to);
    return file(name, p);
  }
  // Refused with exit 2, naming the file and `key`.
  void refused(const std::string& name, const std::string& from, const std::string& to,
               std::initializer_list<std::string> fragments) {
    SCOPED_TRACE(name);
    auto r = expect_refused("run " + edited(name, from, to), 2, fragments);
    EXPECT_NE(r.text.find(name), std::string::npos) << r.text;
  }
};

TEST_F(BadPreset, EmptyBinaryAndMalformedFiles) {
  expect_refused("run " + file("empty.json", ""), 2, {"empty.json"});
  expect_refused("run " + file("nul.json", std::string("{\"format\":\0}", 12)), 2, {"nul.json:1:"});
  expect_refused("run " + file("trunc.json", source("presets/helicopter.json").substr(0, 300)), 2,
                 {"trunc.json:"});
  expect_refused("run " + file("array.json", "[1, 2]"), 2, {"array.json"});
  refused("comma.json", "\"value\": 67.24,", "\"value\": 67.24,,", {"comma.json:9:"});
}

TEST_F(BadPreset, ByteOrderMarkAndCrlfLoad) {
  const std::string p = source("presets/helicopter.json");
  std::string crlf;
  for (char c : p) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  auto a = cli("run " + file("plain.json", p), "2>/dev/null");
  auto b = cli("run " + file("bom.json", "\xEF\xBB\xBF" + p), "2>/dev/null");
  auto c = cli("run " + file("crlf.json", crlf), "2>/dev/null");
  ASSERT_EQ(a.code, 0) << a.text;
  EXPECT_EQ(b.code, 0) << b.text;
  EXPECT_EQ(c.code, 0) << c.text;
  EXPECT_EQ(b.text, a.text);
  EXPECT_EQ(c.text, a.text);
}

TEST_F(BadPreset, NumbersThatOverflowOrAreNotFinite) {
  refused("ovf_value.json", "\"value\": 67.24", "\"value\": 1e999",
          {"parameters.Q.value", "overflows a double"});
  refused("ovf_min.json", "\"min\": 1e-06", "\"min\": -1e999", {"parameters.Q.min", "overflows"});
  refused("ovf_max.json", "\"max\": 1000000.0", "\"max\": 1e400",
          {"parameters.Q.max", "overflows"});
  refused("ovf_version.json", "\"version\": 2", "\"version\": 1e999", {"version"});
  refused("big_version.json", "\"version\": 2", "\"version\": 4294967297", {"version"});
  refused("nan.json", "\"value\": 67.24", "\"value\": NaN", {"nan.json:9:"});
  refused("inf.json", "\"value\": 67.24", "\"value\": Infinity", {"inf.json:9:"});
  refused("nan_text.json", "\"value\": 67.24", "\"value\": \"nan\"", {"parameters.Q.value"});
  refused("huge.json", "\"value\": 67.24", "\"value\": 1e308", {"parameters.Q", "out of range"});
}

TEST_F(BadPreset, WrongTypesAndUnknownKeys) {
  refused("type_value.json", "\"value\": 67.24", "\"value\": \"abc\"", {"parameters.Q.value"});
  refused("type_min.json", "\"min\": 1e-06", "\"min\": [1]", {"parameters.Q.min"});
  refused("type_params.json", "\"parameters\": {", "\"parameters\": 3, \"x\": {", {"parameters"});
  refused("type_scenario.json", "\"scenario\": \"model\"", "\"scenario\": 7", {"scenario"});
  refused("type_tunable.json", "\"tunable\": true", "\"tunable\": \"yes\"",
          {"parameters.Q.tunable"});
  refused("unknown_key.json", "\"title\"", "\"titel\"", {"titel"});
  // A model file (issue 27): its expressions name the parameter that the edit renamed.
  refused("unknown_param.json", "\"Q\": {", "\"Qq\": {", {"model.expressions", "'Q'"});
  refused("unknown_scenario.json", "\"scenario\": \"model\"", "\"scenario\": \"modle\"",
          {"scenario", "did you mean 'model'"});
  refused("bad_format.json", "\"kfw-preset\"", "\"kfw-session\"", {"format"});
  // A model file declares its parameters' units (issue 27): a unit that is not text is the error.
  refused("bad_unit.json", "\"unit\": \"(deg/s)²\"", "\"unit\": 5", {"parameters.Q.unit"});
}

TEST_F(BadPreset, OutOfRangeZeroAndNegativeVariances) {
  refused("above.json", "\"value\": 67.24", "\"value\": 2e6", {"parameters.Q", "range"});
  refused("zero_var.json", "\"value\": 67.24", "\"value\": 0", {"parameters.Q"});
  refused("neg_var.json", "\"value\": 1.96", "\"value\": -1", {"parameters.R"});
  refused("min_gt_max.json", "\"min\": 1e-06", "\"min\": 1e7", {"parameters.Q"});
  // A model file declares its own ranges (issue 27): a log scale below zero is the error.
  refused("min_outside.json", "\"min\": 1e-06", "\"min\": -5", {"parameters.Q", "log scale"});
  refused("m_fraction.json", "\"value\": 1.0,\n      \"min\": 1.0",
          "\"value\": 1.5,\n      \"min\": 1.0", {"parameters.m"});
}

TEST_F(BadPreset, LimitsAreRefusedAtOnce) {
  const auto start = std::chrono::steady_clock::now();
  std::string deep = std::string(300, '[') + std::string(300, ']');
  refused("deep.json", "\"description\": \"", "\"x\": " + deep + ", \"description\": \"",
          {"deep.json:", "256"});
  refused("big.json", "\"description\": \"", "\"description\": \"" + std::string(11u << 20, 'a'),
          {"big.json", "10 MB"});
  EXPECT_LT(std::chrono::steady_clock::now() - start,
            std::chrono::seconds(10) * testing::kTimeScale);
}

TEST_F(BadPreset, DataPathsThatAreMissingOrDirectories) {
  refused("no_data.json", "\"parameters\"", "\"data\": \"absent.csv\", \"parameters\"",
          {"absent.csv", "data"});
  std::filesystem::create_directories(dir / "folder.csv");
  refused("dir_data.json", "\"parameters\"", "\"data\": \"folder.csv\", \"parameters\"",
          {"folder.csv", "directory"});
  refused("type_data.json", "\"parameters\"", "\"data\": 5, \"parameters\"", {"data"});
  refused("bad_mapping.json", "\"parameters\"",
          "\"data\": \"x.csv\", \"mapping\": {\"gyro\": {\"unit\": \"furlong\"}}, \"parameters\"",
          {"mapping.gyro.unit"});
}

// Found by the fuzz corpus replay (tests/fuzz/harness.h: a loaded preset is written and re-read).
TEST_F(BadPreset, WrittenPresetsReadBack) {
  // A preset named without a folder, with a data file: `preset` aborted (absolute("") threw).
  file("d.csv", "t,gyro,angle\n0,1,2\n0.02,1,2\n");
  std::string p = source("presets/helicopter.json");
  p.replace(p.find("\"parameters\""), 0, "\"data\": \"d.csv\", ");
  file("p.json", p);
  auto w = testing::run_command("cd " + dir.string() + " && " + KFW_CLI +
                                " preset p.json --out x.json 2>&1");
  ASSERT_EQ(w.code, 0) << w.text;
  EXPECT_NE(read((dir / "x.json").string()).find("\"data\": \"d.csv\""), std::string::npos);
  // A model preset written by `preset` (the filter choice as its index) loads again.
  const std::string cv = (dir / "cv.json").string();
  ASSERT_EQ(
      cli("preset " + std::string(KFW_SOURCE_DIR) + "/presets/models/cv1d.json --out " + cv).code,
      0);
  auto r = cli("run " + cv + " --set filter=ukf", "2>/dev/null");
  EXPECT_EQ(r.code, 0) << r.text;
}

}  // namespace
}  // namespace kfw
