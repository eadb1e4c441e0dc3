// Issue 32, item 15: a preset written somewhere else than the one it came from still finds its
// data. `kfw-cli preset` and `tune --out` write the data path relative to where the new file goes
// (they wrote the source preset's relative path verbatim: "../../shared/…" broke in ~/t.json).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "common/cli_runner.h"
#include "common/short_temp_dir.h"

namespace kfw {
namespace preset_paths_cli_test {
namespace {

namespace fs = std::filesystem;
using testing::cli;

class PresetPathsCli : public testing::ShortTempDir {
 protected:
  // dir_/src/p.json: the helicopter preset reading dir_/src/log.csv as "log.csv".
  std::string source() {
    fs::create_directories(dir_ + "/src");
    fs::create_directories(dir_ + "/out/deeper");
    const auto sim = cli("simulate helicopter --set sim.duration=5 --out " + dir_ + "/src/log.csv");
    EXPECT_EQ(sim.code, 0) << sim.text;
    std::ifstream in(std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json");
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(in);
    j["data"] = "log.csv";
    return write("src/p.json", j.dump(2));
  }
  static std::string data_of(const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in).at("data").get<std::string>();
  }
};

TEST_F(PresetPathsCli, PresetOutRebasesTheDataPath) {
  const std::string p = source();
  const std::string out = dir_ + "/out/deeper/q.json";
  const auto w = cli("preset " + p + " --set Q=2 --out " + out);
  ASSERT_EQ(w.code, 0) << w.text;
  EXPECT_EQ(data_of(out), "../../src/log.csv");
  const auto run = cli("run " + out, "2>&1 >/dev/null");
  EXPECT_EQ(run.code, 0) << run.text;
  // The same file written beside its source keeps the plain name.
  ASSERT_EQ(cli("preset " + p + " --out " + dir_ + "/src/r.json").code, 0);
  EXPECT_EQ(data_of(dir_ + "/src/r.json"), "log.csv");
}

TEST_F(PresetPathsCli, TuneOutRebasesTheDataPath) {
  const std::string p = source();
  const std::string out = dir_ + "/out/t.json";
  const auto t = cli("tune " + p + " --params Q --budget 12 --out " + out, "2>&1 >/dev/null");
  ASSERT_EQ(t.code, 0) << t.text;
  EXPECT_EQ(data_of(out), "../src/log.csv");
  const auto run = cli("run " + out, "2>&1 >/dev/null");
  EXPECT_EQ(run.code, 0) << run.text;
}

// Issue 32, item 15: `kfw … cv1d` names no shipped preset; the model file of that name is
// suggested (the window's loader says the same: open_workspace).
TEST(PresetNamesCli, AModelFilesNameSuggestsItsPath) {
  const auto o = cli("run cv1d");
  EXPECT_EQ(o.code, 2) << o.text;
  EXPECT_NE(o.text.find("did you mean 'models/cv1d'?"), std::string::npos) << o.text;
  const auto near = cli("run helicoptr");
  EXPECT_EQ(near.code, 2) << near.text;
  EXPECT_NE(near.text.find("did you mean 'helicopter'?"), std::string::npos) << near.text;
}

}  // namespace
}  // namespace preset_paths_cli_test
}  // namespace kfw
