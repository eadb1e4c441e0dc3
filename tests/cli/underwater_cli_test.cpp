// The underwater preset through kfw-cli: simulate → stats and run, as a user would. Issue 27:
// presets/underwater.json is a model file; `stats` prints its covariance block (seed 004, eqs.
// 5–8) and its channels' outlier counts (engine/model/model_stats.h).
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "common/cli_runner.h"

namespace {

using kfw::testing::cli;

std::string temp_csv(const std::string& stem) {
  return (std::filesystem::temp_directory_path() /
          (stem + "_" + std::to_string(::getpid()) + ".csv"))
      .string();
}

// Copies a CSV without the columns whose names `drop` accepts.
template <class Drop>
void copy_without(const std::string& from, const std::string& to, Drop drop) {
  std::ifstream in(from);
  std::ofstream out(to);
  std::string line;
  std::vector<bool> keep;
  while (std::getline(in, line)) {
    std::string row;
    bool first = true;
    std::size_t start = 0;
    for (std::size_t i = 0; start <= line.size(); ++i) {
      std::size_t end = line.find(',', start);
      if (end == std::string::npos) end = line.size();
      const std::string cell = line.substr(start, end - start);  // empty cells kept
      if (keep.size() <= i) keep.push_back(!drop(cell));
      if (keep[i]) {
        row += (first ? "" : ",") + cell;
        first = false;
      }
      start = end + 1;
    }
    out << row << "\n";
  }
}

TEST(UnderwaterCli, SimulateThenStatsReproducesGaussianDesign) {
  const std::string csv = temp_csv("uw_gauss");
  // Gaussian only (seed 004, Sec. 4.1), synchronous clocks.
  const std::string sets =
      " --set sim.clock=synchronous --set sim.sigma_corr=0 --set sim.outliers=0 --set "
      "sim.duration=600";
  auto s = cli("simulate underwater --out " + csv + sets);
  ASSERT_EQ(s.code, 0) << s.text;
  auto st = cli("stats underwater --data " + csv + sets);
  ASSERT_EQ(st.code, 0) << st.text;
  const auto j = nlohmann::json::parse(st.text);
  const auto& b = j["blocks"]["covariance"];
  ASSERT_EQ(b["series"].size(), 5u) << st.text;
  EXPECT_EQ(b["samples"].get<int>(), 6000);  // one instant per 0.1 s
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(b["covariance"][i][i].get<double>(), 0.01, 0.0015);
  EXPECT_NEAR(b["covariance"][4][4].get<double>(), 0.04, 0.006);
  double cov = 0.0;  // the mean covariance between two beacons' range errors
  for (int i = 0; i < 4; ++i) {
    for (int k = i + 1; k < 4; ++k)
      cov += b["covariance"][i][k].get<double>() / 6.0;
  }
  EXPECT_NEAR(cov, 0.0, 0.001);
  // Beside it the filter's R: σ_r² + σ_c² on the diagonal (the filter's own 0.1 and 0.2 m).
  EXPECT_NEAR(b["design"][0][0].get<double>(), 0.05, 1e-12);
  EXPECT_NEAR(b["design"][0][1].get<double>(), 0.04, 1e-12);
  EXPECT_EQ(j["outliers_injected"].get<int>(), 0);
  std::filesystem::remove(csv);
}

// Seed 004 eqs. 5–8: with the correlated term on, the off-diagonal covariance of the range errors
// is σ_c², and the file's shorthand `stats FILE.csv` finds the one shipped preset offering it.
TEST(UnderwaterCli, StatsShowTheCorrelatedRangeNoise) {
  const std::string csv = temp_csv("uw_corr");
  const std::string sets =
      " --set sim.clock=synchronous --set sim.outliers=0 --set "
      "sim.duration=1200 --set sim.t_gap=0.1";
  ASSERT_EQ(cli("simulate underwater --out " + csv + sets).code, 0);
  auto st = cli("stats " + csv + sets);
  ASSERT_EQ(st.code, 0) << st.text;
  const auto b = nlohmann::json::parse(st.text)["blocks"]["covariance"];
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(b["covariance"][i][i].get<double>(), 0.05, 0.006) << i;
    for (int k = i + 1; k < 4; ++k)
      EXPECT_NEAR(b["covariance"][i][k].get<double>(), 0.04, 0.006) << i << k;
  }
  std::filesystem::remove(csv);
}

TEST(UnderwaterCli, RunPrintsTheTable13Metrics) {
  auto r = cli("run underwater --set scheme=AS");
  ASSERT_EQ(r.code, 0) << r.text;
  const auto j = nlohmann::json::parse(r.text.substr(r.text.find('{')));
  for (const char* k : {"derived.pos_err.rms", "derived.pos_err.max", "rmse", "outliers_injected",
                        "outliers_detected", "outliers_false_alarm", "nees_mean", "gated.range1"}) {
    EXPECT_TRUE(j.contains(k)) << k;
  }
  EXPECT_EQ(j["outliers_injected"].get<double>(), 276.0);
  // The position RMSE is the RMS distance error.
  EXPECT_NEAR(j["rmse"].get<double>(), j["derived.pos_err.rms"].get<double>(), 1e-9);
  // NEES / dof (3 for x, y, z): 1.967 / 3 with the built-in on the same data.
  EXPECT_NEAR(j["nees_mean"].get<double>(), 1.967 / 3.0, 0.01);
}

// A log without the injected-outlier columns: which rejections were outliers is unknown, so
// `run` reports the outlier counts as undefined (no number) and `stats` prints them as null.
TEST(UnderwaterCli, OutlierCountsAreNullWithoutInjectedColumns) {
  const std::string csv = temp_csv("uw_full");
  const std::string sets = " --set sim.clock=synchronous --set sim.duration=120";
  ASSERT_EQ(cli("simulate underwater --out " + csv + sets).code, 0);
  const std::string cut = temp_csv("uw_no_outliers");
  copy_without(csv, cut, [](const std::string& c) { return c.rfind("outlier", 0) == 0; });
  auto r = cli("run underwater --data " + cut + sets);
  ASSERT_EQ(r.code, 0) << r.text;
  const auto j = nlohmann::json::parse(r.text.substr(r.text.find('{')));
  for (const char* k : {"outliers_injected", "outliers_detected", "outliers_false_alarm"}) {
    EXPECT_FALSE(j.contains(k)) << k << " = " << j[k];
    if (j.contains("undefined")) {
      EXPECT_TRUE(j["undefined"].contains(k)) << k;
    }
  }
  double gated = 0.0;
  for (int b = 1; b <= 4; ++b)
    gated += j["gated.range" + std::to_string(b)].get<double>();
  EXPECT_GT(gated, 0.0);
  EXPECT_TRUE(j["nees_mean"].is_number());
  auto st = cli("stats underwater --data " + cut + sets);
  ASSERT_EQ(st.code, 0) << st.text;
  const auto js = nlohmann::json::parse(st.text);
  for (const char* k : {"outliers_injected", "outliers_detected", "outliers_false_alarm"}) {
    EXPECT_TRUE(js[k].is_null()) << k << " = " << js[k];
  }
  // With the columns the same counts are numbers.
  const auto full = nlohmann::json::parse(cli("stats underwater --data " + csv + sets).text);
  EXPECT_TRUE(full["outliers_false_alarm"].is_number());
  EXPECT_EQ(full["outliers_injected"].get<int>(), 276);
  std::filesystem::remove(csv);
  std::filesystem::remove(cut);
}

// The EKF's Jacobians are printed from GiNaC, which ordered their terms by hashes of addresses:
// each process summed them in its own order and the estimates differed in the last bits. Three
// processes write the same bytes.
TEST(UnderwaterCli, ProcessesWriteTheSameEstimates) {
  std::string first;
  for (int i = 0; i < 3; ++i) {
    const std::string out = temp_csv("uw_same" + std::to_string(i));
    auto r = cli("run underwater --set sim.duration=10 --set q_pos=0.5 --out " + out);
    ASSERT_EQ(r.code, 0) << r.text;
    std::ifstream in(out);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(text.size(), 1000u);
    if (i == 0) {
      first = text;
    } else {
      EXPECT_TRUE(text == first) << "process " << i << " wrote other numbers";
    }
    std::filesystem::remove(out);
  }
}

TEST(UnderwaterCli, MissingBeaconColumnIsAClearError) {
  const std::string csv = temp_csv("uw_missing");
  ASSERT_EQ(cli("simulate underwater --set sim.duration=5 --out " + csv).code, 0);
  const std::string cut = temp_csv("uw_cut");
  copy_without(csv, cut, [](const std::string& c) { return c == "range3"; });
  auto r = cli("run underwater --data " + cut);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.text.find("range3"), std::string::npos) << r.text;
  std::filesystem::remove(csv);
  std::filesystem::remove(cut);
}

}  // namespace
