// The underwater scenario through kfw-cli: simulate → stats and run, as a user would.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
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
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(j["covariance"][i][i].get<double>(), 0.01, 0.0015);
  EXPECT_NEAR(j["covariance"][4][4].get<double>(), 0.04, 0.006);
  EXPECT_NEAR(j["range_cov_mean"].get<double>(), 0.0, 0.001);
  EXPECT_EQ(j["outliers_injected"].get<int>(), 0);
  std::filesystem::remove(csv);
}

TEST(UnderwaterCli, RunPrintsTheTable13Metrics) {
  auto r = cli("run underwater --set scheme=AS");
  ASSERT_EQ(r.code, 0) << r.text;
  const auto j = nlohmann::json::parse(r.text.substr(r.text.find('{')));
  for (const char* k : {"pos_mean", "pos_std", "pos_max", "rmse", "outliers_injected",
                        "outliers_detected", "outliers_false_alarm", "nees_mean"}) {
    EXPECT_TRUE(j.contains(k)) << k;
  }
  EXPECT_EQ(j["outliers_injected"].get<double>(), 276.0);
  // NEES / dof (3 for x, y, z): 1.967 / 3.
  EXPECT_NEAR(j["nees_mean"].get<double>(), 1.967 / 3.0, 0.01);
}

// A log without the injected-outlier columns: which rejections were outliers is unknown, so
// `run` reports the outlier counts as undefined (no number) and `stats` prints them as null.
TEST(UnderwaterCli, OutlierCountsAreNullWithoutInjectedColumns) {
  const std::string csv = temp_csv("uw_full");
  const std::string sets = " --set sim.clock=synchronous --set sim.duration=120";
  ASSERT_EQ(cli("simulate underwater --out " + csv + sets).code, 0);
  // outlier1..4 are the last four of the 26 columns.
  const std::string cut = temp_csv("uw_no_outliers");
  ASSERT_EQ(std::system(("cut -d, -f1-22 " + csv + " > " + cut).c_str()), 0);
  auto r = cli("run underwater --data " + cut + sets);
  ASSERT_EQ(r.code, 0) << r.text;
  const auto j = nlohmann::json::parse(r.text.substr(r.text.find('{')));
  for (const char* k : {"outliers_injected", "outliers_detected", "outliers_false_alarm"}) {
    EXPECT_FALSE(j.contains(k)) << k << " = " << j[k];
    if (j.contains("undefined")) {
      EXPECT_TRUE(j["undefined"].contains(k)) << k;
    }
  }
  EXPECT_GT(j["ranges_rejected"].get<double>(), 0.0);
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

TEST(UnderwaterCli, MissingBeaconColumnIsAClearError) {
  const std::string csv = temp_csv("uw_missing");
  ASSERT_EQ(cli("simulate underwater --set sim.duration=5 --out " + csv).code, 0);
  // Drop the range3 column (the 13th) from header and rows.
  const std::string cut = temp_csv("uw_cut");
  const std::string drop = "cut -d, -f1-12,14- " + csv + " > " + cut;
  ASSERT_EQ(std::system(drop.c_str()), 0);
  auto r = cli("run underwater --data " + cut);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.text.find("range3"), std::string::npos) << r.text;
  std::filesystem::remove(csv);
  std::filesystem::remove(cut);
}

}  // namespace
