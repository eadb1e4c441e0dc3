// Hardening round 2 (issue 29): accepted-when-invalid inputs now refused, and messages that name
// the file, the key and what to try (each case failed before its fix: accepted, or a vague or
// wrong message).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "common/cli_runner.h"
#include "common/short_temp_dir.h"

namespace kfw {
namespace {

using nlohmann::json;
using testing::cli;

const std::string kMsgHeli = std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json";
const std::string kMsgCv1d = std::string(KFW_SOURCE_DIR) + "/presets/models/cv1d.json";
const std::string kMsgHeliCsv = std::string(KFW_SOURCE_DIR) + "/data/helicopter.csv";

class Messages : public testing::ShortTempDir {
 protected:
  std::string cv1d_with(const std::string& name, const std::function<void(json&)>& edit) const {
    std::ifstream in(kMsgCv1d);
    json j = json::parse(in);
    edit(j);
    return write(name, j.dump());
  }
  void refused(const std::string& args, const std::string& fragment, int code = 2) {
    auto r = cli(args);
    EXPECT_EQ(r.code, code) << args << "\n" << r.text;
    EXPECT_NE(r.text.find(fragment), std::string::npos)
        << "'" << fragment << "' not in: " << r.text;
  }
};

TEST_F(Messages, ImportOptionsWithoutFileDataAreRefused) {
  refused("run " + kMsgHeli + " --map gyro=omega", "--map: applies to file data");
  refused("run " + kMsgHeli + " --time time_ms:ms", "--time: applies to file data");
  auto ok =
      cli("run " + kMsgHeli + " --data " + kMsgHeliCsv + " --map gyro=gyro", "2>&1 >/dev/null");
  EXPECT_EQ(ok.code, 0) << ok.text;
}

TEST_F(Messages, IsoTimesWithImpossibleOffsetsOrLeapSecondsAreNamed) {
  const auto file = [&](const std::string& first) {
    return write("iso.csv", "time,gyro,angle\n" + first +
                                ",1,2\n2030-01-01T00:00:01Z,1,2\n2030-01-01T00:00:02Z,1,2\n");
  };
  refused("run " + kMsgHeli + " --data " + file("2030-01-01T00:00:00+25:00") + " --time time:iso",
          "the UTC offset +25:00 is out of range");
  refused("run " + kMsgHeli + " --data " + file("2016-12-31T23:59:60Z") + " --time time:iso",
          "is a leap second");
}

TEST_F(Messages, AMappingFileWithAnUnknownRoleSaysSo) {
  const std::string m = write("map.json", R"({"gyr": "gyro"})");
  refused("run " + kMsgHeli + " --data " + kMsgHeliCsv + " --mapping " + m,
          m + ": mapping.gyr: unknown role 'gyr' (did you mean 'gyro'?)");
}

TEST_F(Messages, BlanksInAColumnNameSuggestTheWhitespaceSeparator) {
  const std::string f = write("mixed.csv", "t\tgyro angle\n0\t1 2\n0.1\t1 2\n0.2\t1 2\n");
  refused("run " + kMsgHeli + " --data " + f, "read the file with --sep whitespace");
  auto ok = cli("run " + kMsgHeli + " --data " + f + " --sep whitespace", "2>&1 >/dev/null");
  EXPECT_EQ(ok.code, 0) << ok.text;
}

TEST_F(Messages, ModelFileValuesThatCanNeverWorkAreRefusedAtLoad) {
  const std::string inf =
      cv1d_with("inf.json", [](json& j) { j["model"]["process"]["F"][0][1] = "-1e308*10"; });
  refused("params " + inf, "model.process.F[0][1]: \"-1e308*10\" is the constant -inf");
  const std::string qinf = cv1d_with("qinf.json", [](json& j) {
    j["model"]["process"]["Q"][1][1] = "dt^2*sigma_a^2*1e308/dt^3*1e10";
  });
  refused("run " + qinf, "model.process.Q: not finite at dt = 0.1 s");
  const std::string name =
      cv1d_with("name.json", [](json& j) { j["model"]["states"][0] = std::string(5000, 'a'); });
  refused("params " + name, "model.states[0]");
  refused("params " + name, "a name of 5000 characters");
}

TEST_F(Messages, ANoiseFreeSensorIsNotCalledAMissingTruthColumn) {
  const std::string r0 = cv1d_with("r0.json", [](json& j) {
    j["model"]["measurements"].begin().value()["R"] = json::array({"0"});
  });
  auto r = cli("run " + r0, "2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.text;
  const json m = json::parse(r.text);
  const std::string why = m.at("undefined").at("nees_mean");
  EXPECT_EQ(why.find("no truth column"), std::string::npos) << why;
  EXPECT_NE(why.find("R = 0"), std::string::npos) << why;
}

// An angle column of 1e308: the estimate follows it and the error's square overflows; the NEES
// was blamed on a singular covariance ("R = 0?") although R = 1.96.
TEST_F(Messages, AnOverflowingErrorIsNotCalledASingularCovariance) {
  std::ifstream in(kMsgHeliCsv);
  std::string header, line, text;
  std::getline(in, header);
  text = header + "\n";
  for (int k = 0; k < 200 && std::getline(in, line); ++k) {
    // t,angle,gyro,bias_truth,truth: the angle (second cell) set to 1e308
    const auto a = line.find(','), b = line.find(',', a + 1);
    text += line.substr(0, a + 1) + "1e308" + line.substr(b) + "\n";
  }
  ASSERT_EQ(header.substr(0, 8), "t,angle,");
  const std::string csv = write("big_angle.csv", text);
  auto r = cli("run " + kMsgHeli + " --data " + csv, "2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.text;
  const std::string why = json::parse(r.text).at("undefined").at("nees_mean");
  EXPECT_NE(why.find("the estimation error overflows"), std::string::npos) << why;
}

TEST_F(Messages, ControlBytesFromAFileAreNeverEchoedRaw) {
  std::ifstream in(kMsgHeli);
  json p = json::parse(in);
  p["format"] = std::string("kfw-pre\0set", 11);
  auto r = cli("run " + write("nul.json", p.dump()));
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find("'kfw-pre\\x00set'"), std::string::npos) << r.text;
  EXPECT_EQ(r.text.find('\0'), std::string::npos);
  const std::string m = write("nulmap.json", json{{"gyro", std::string("gy\0ro", 5)}}.dump());
  auto mr = cli("run " + kMsgHeli + " --data " + kMsgHeliCsv + " --mapping " + m);
  EXPECT_EQ(mr.code, 2) << mr.text;
  EXPECT_NE(mr.text.find("'gy\\x00ro'"), std::string::npos) << mr.text;
}

}  // namespace
}  // namespace kfw
