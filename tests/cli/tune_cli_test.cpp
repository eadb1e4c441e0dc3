// kfw-cli tune, sweep --shard and merge: issue 14's acceptance on the command line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/cli_runner.h"

namespace kfw {
namespace {

using testing::cli;
using testing::run_command;
namespace fs = std::filesystem;

const std::string kPresets = std::string(KFW_SOURCE_DIR) + "/presets/";
const std::string kRealLog =
    std::string(KFW_SHARED_DIR) + "/data/broad/10_undisturbed_slow_translation_A.csv";

class TuneCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("kfw_tune_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static std::string read(const std::string& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }
  fs::path dir_;
};

nlohmann::json json_of(const std::string& text) {
  return nlohmann::json::parse(text, nullptr, false);
}

// Acceptance: tune with the default selection and objective succeeds on every preset and model.
TEST_F(TuneCli, DefaultObjectiveSucceedsOnEveryPreset) {
  std::vector<std::string> presets = {"helicopter", "radome", "ballbeam", "underwater"};
  if (fs::exists(kRealLog)) presets.push_back("broad_imu");
  for (const auto& e : fs::directory_iterator(kPresets + "models")) {
    if (e.path().extension() == ".json") presets.push_back(e.path().string());
  }
  for (const auto& p : presets) {
    auto r = cli("tune " + p + " --budget 25", "2>/dev/null");
    ASSERT_EQ(r.code, 0) << p << ": " << cli("tune " + p + " --budget 25").text;
    auto j = json_of(r.text);
    ASSERT_FALSE(j.is_discarded()) << p;
    EXPECT_FALSE(j["params"].empty()) << p;
    EXPECT_TRUE(j.contains("value")) << p;
  }
}

// Acceptance: plain rmse over {Q, R} on the helicopter simulation reports the scale as
// undetermined (JSON and a warning), and sets it by consistency.
TEST_F(TuneCli, RmseOverQAndRReportsTheScaleUndetermined) {
  auto r = cli("tune helicopter --params Q,R --objective rmse --budget 120 --set sim.duration=60",
               "2>" + path("err.txt"));
  ASSERT_EQ(r.code, 0) << r.text << read(path("err.txt"));
  auto j = json_of(r.text);
  ASSERT_EQ(j["scale"].size(), 1u);
  EXPECT_FALSE(j["scale"][0]["determined_by_objective"].get<bool>());
  EXPECT_TRUE(j["scale"][0]["set_by_consistency"].get<bool>());
  EXPECT_NEAR(j["metrics"]["nis_mean"].get<double>(), 1.0, 0.02);
  EXPECT_NE(read(path("err.txt")).find("does not change when Q, R scale together"),
            std::string::npos);
  // Bad settings are refused before any work.
  EXPECT_EQ(cli("tune helicopter --params m").code, 2);
  EXPECT_NE(cli("tune helicopter --params m").text.find("not tunable"), std::string::npos);
  EXPECT_NE(cli("tune helicopter --method bobyq").text.find("did you mean 'bobyqa'"),
            std::string::npos);
  EXPECT_EQ(cli("tune helicopter --params Q --lo Q=10 --hi Q=1").code, 2);
  EXPECT_EQ(cli("tune helicopter --params Q --lo R=10").code, 2);
  EXPECT_EQ(cli("tune helicopter --data '" + path("none*.csv") + "'").code, 2);
}

// A bound hit is reported.
TEST_F(TuneCli, BoundHitIsReported) {
  auto r = cli("tune helicopter --params R --objective rmse --hi R=0.1 --lo R=0.01 --budget 40",
               "2>" + path("err.txt"));
  ASSERT_EQ(r.code, 0) << r.text;
  EXPECT_EQ(json_of(r.text)["at_bound"], nlohmann::json::array({"R"}));
  EXPECT_NE(read(path("err.txt")).find("search bound for R"), std::string::npos);
}

// Acceptance: two copies of the real log tune exactly as the log alone.
TEST_F(TuneCli, TwoCopiesOfTheRealLogEqualTheSingleLogTune) {
  if (!fs::exists(kRealLog)) GTEST_SKIP() << "shared data not present";
  const std::string base =
      "tune " + kPresets + "broad_imu.json --params Q,R,gamma --objective rmse";
  auto one = cli(base, "2>/dev/null");
  auto two = cli(base + " --data " + kRealLog + " --data " + kRealLog, "2>/dev/null");
  ASSERT_EQ(one.code, 0);
  ASSERT_EQ(two.code, 0);
  auto j1 = json_of(one.text), j2 = json_of(two.text);
  EXPECT_EQ(j1["params"], j2["params"]);
  EXPECT_EQ(j1["value"], j2["value"]);
  EXPECT_LT(j1["value"].get<double>(), 1.5635);  // keeps the Nelder–Mead 1.563°
  ASSERT_EQ(j2["logs"].size(), 2u);
  EXPECT_EQ(j2["logs"][0]["value"], j2["logs"][1]["value"]);
}

// Acceptance: with a second, different simulated log the aggregate is reported per log.
TEST_F(TuneCli, ADifferentLogIsReportedPerLog) {
  ASSERT_EQ(cli("simulate helicopter --seed 1 --set sim.duration=30 --out " + path("a.csv")).code,
            0);
  ASSERT_EQ(
      cli("simulate helicopter --seed 2 --set sim.duration=30 --set sim.sigma_angle=3 --out " +
          path("b.csv"))
          .code,
      0);
  for (const char* agg : {"mean", "worst"}) {
    auto r = cli("tune helicopter --params Q,gamma --objective rmse --budget 60 --data '" +
                     path("*.csv") + "' --aggregate " + agg,
                 "2>/dev/null");
    ASSERT_EQ(r.code, 0) << r.text;
    auto j = json_of(r.text);
    ASSERT_EQ(j["logs"].size(), 2u);
    EXPECT_EQ(j["logs"][0]["data"], path("a.csv"));
    EXPECT_EQ(j["logs"][1]["data"], path("b.csv"));
    const double a = j["logs"][0]["value"], b = j["logs"][1]["value"];
    EXPECT_GT(b, a);  // the noisier sensor
    EXPECT_DOUBLE_EQ(j["value"].get<double>(), std::string(agg) == "mean" ? (a + b) / 2 : b);
  }
}

// tune --seeds: the tuning set is the datasets of the seeds, the same as those logs given with
// --data.
TEST_F(TuneCli, SeedsTuneLikeTheirSimulatedLogs) {
  for (int seed : {1, 2}) {
    ASSERT_EQ(cli("simulate helicopter --seed " + std::to_string(seed) +
                  " --set sim.duration=20 --out " + path("s" + std::to_string(seed) + ".csv"))
                  .code,
              0);
  }
  const std::string base =
      "tune helicopter --params Q,gamma --objective rmse --budget 40 "
      "--set sim.duration=20 ";
  auto by_seeds = cli(base + "--seeds 1..2", "2>/dev/null");
  auto by_logs =
      cli(base + "--data " + path("s1.csv") + " --data " + path("s2.csv"), "2>/dev/null");
  ASSERT_EQ(by_seeds.code, 0) << by_seeds.text;
  ASSERT_EQ(by_logs.code, 0) << by_logs.text;
  auto js = json_of(by_seeds.text), jl = json_of(by_logs.text);
  EXPECT_EQ(js["seeds"], 2);
  ASSERT_EQ(js["logs"].size(), 2u);
  EXPECT_EQ(js["logs"][0]["data"], "seed 1");
  EXPECT_EQ(js["logs"][1]["data"], "seed 2");
  EXPECT_EQ(js["params"], jl["params"]);
  EXPECT_DOUBLE_EQ(js["value"].get<double>(), jl["value"].get<double>());
  EXPECT_NE(js["logs"][0]["value"], js["logs"][1]["value"]);
  // Seeds simulate: not with a dataset.
  auto refused = cli(base + "--seeds 1..2 --data " + path("s1.csv"));
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.text.find("--seeds"), std::string::npos) << refused.text;
}

// Acceptance: a sweep in 4 shards run through GNU parallel merges to the unsharded result,
// byte for byte; the cap applies per shard.
TEST_F(TuneCli, ShardedSweepThroughParallelMergesExactly) {
  if (run_command("command -v parallel").code != 0) GTEST_SKIP() << "GNU parallel not installed";
  const std::string sweep = std::string(KFW_CLI) +
                            " sweep helicopter --set sim.duration=20 --param Q=1:1000:7 "
                            "--param gamma=0:0.02:5 --metric nis_mean";
  auto whole = run_command(sweep + " --out " + path("all.json") + " 2>&1");
  ASSERT_EQ(whole.code, 0) << whole.text;
  auto par = run_command("parallel --will-cite " + sweep + " --shard {}/4 --out " +
                         path("part_{}.json") + " ::: 1 2 3 4 2>&1");
  ASSERT_EQ(par.code, 0) << par.text;
  auto merged = cli("merge " + path("part_*.json") + " --out " + path("merged.json"));
  ASSERT_EQ(merged.code, 0) << merged.text;
  EXPECT_EQ(merged.text, whole.text);  // the same summary: best, best_at, points
  EXPECT_EQ(read(path("merged.json")), read(path("all.json")));
  auto part = json_of(read(path("part_2.json")));
  EXPECT_EQ(part["kind"], "sweep");
  EXPECT_EQ(part["points"].size(), 9u);  // indices 1, 5, …, 33 of 35
  // A missing shard, a shard given twice and an unknown kind are refused.
  EXPECT_EQ(cli("merge " + path("part_1.json") + " " + path("part_2.json")).code, 2);
  EXPECT_EQ(cli("merge " + path("part_1.json") + " " + path("part_1.json")).code, 2);
  std::ofstream(path("odd.json")) << R"({"kind": "montecarl"})";
  EXPECT_NE(cli("merge " + path("odd.json")).text.find("unknown kind 'montecarl'"),
            std::string::npos);
  // The cap applies per shard: 35 points in 4 shards are at most 9 each.
  EXPECT_EQ(run_command(sweep + " --shard 1/4 --out " + path("p.json") + " --max-points 9").code,
            0);
  EXPECT_EQ(run_command(sweep + " --shard 1/4 --out " + path("p.json") + " --max-points 8").code,
            2);
  EXPECT_EQ(run_command(sweep + " --shard 1/4").code, 2);  // a part needs --out PART.json
}

}  // namespace
}  // namespace kfw
