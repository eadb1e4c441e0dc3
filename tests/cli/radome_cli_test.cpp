// kfw-cli on the radome preset: the three seed 001 reproduction runs and one-line errors.
#include <gtest/gtest.h>

#include "common/cli_runner.h"

#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

namespace {

using Out = kfw::testing::CliOutput;
using kfw::testing::cli;

const std::string kRadome = std::string(KFW_SOURCE_DIR) + "/presets/radome.json";

nlohmann::json run(const std::string& sets) {
  auto o = cli("run " + kRadome + " " + sets);
  EXPECT_EQ(o.code, 0) << o.text;
  return nlohmann::json::parse(o.text);
}

TEST(RadomeCli, ReproducesSeed001) {
  const auto a = run("--set sim.amplitude=0.05 --set Kp=0");
  const auto b = run("--set sim.amplitude=0.08 --set Kp=0");
  const auto c = run("--set sim.amplitude=0.08 --set Kp=0.45");
  for (const char* k : {"slope_rmse_psi", "slope_rmse_theta", "refraction_err_max_deg",
                        "grid_center_psi_final", "grid_center_theta_final"}) {
    ASSERT_TRUE(a.contains(k) && a[k].is_number()) << k;
  }
  EXPECT_LT(a["refraction_err_max_deg"].get<double>(), 0.5);                              // Fig. 4
  EXPECT_GT(b["slope_rmse_psi"].get<double>(), 2 * a["slope_rmse_psi"].get<double>());    // Fig. 5
  EXPECT_LT(c["slope_rmse_psi"].get<double>(), 0.5 * b["slope_rmse_psi"].get<double>());  // Fig. 7
  EXPECT_LT(c["slope_rmse_theta"].get<double>(), 0.5 * b["slope_rmse_theta"].get<double>());
  EXPECT_GT(c["grid_center_psi_max_abs"].get<double>(), 0.05);  // Fig. 9: the grid moves out
  // The simulated data carry the true position: NEES of the combined position divided by its
  // 3 dof (60.70, 1632.6, 77.53 before the division).
  for (const auto* m : {&a, &b, &c})
    ASSERT_TRUE(m->contains("nees_mean") && (*m)["nees_mean"].is_number());
  EXPECT_NEAR(a["nees_mean"].get<double>(), 60.70 / 3, 0.1);
  EXPECT_NEAR(b["nees_mean"].get<double>(), 1632.6 / 3, 5.0);
  // renewal.mode=mix: a chaotic run (the built-in against itself with ranges × (1 + 1e-13)
  // drifts by several σ by 60 s, tests/engine/imm_model_radome_test.cpp), so two implementations
  // agree on its NEES to a few per cent, not to 0.1 (the model file: 76.12 / 3; issue 28).
  EXPECT_NEAR(c["nees_mean"].get<double>(), 77.53 / 3, 0.05 * 77.53 / 3);
}

TEST(RadomeCli, EqualGridEndsAreAWarningNamingTheKeys) {
  const auto o = cli("run " + kRadome + " --set grid.min=0 --set grid.max=0");
  EXPECT_EQ(o.code, 0) << o.text;
  EXPECT_NE(o.text.find("warning: grid.min = grid.max"), std::string::npos) << o.text;
}

TEST(RadomeCli, BadGridIsAOneLineError) {
  auto o = cli("run " + kRadome + " --set grid.min=0.1 --set grid.max=-0.1");
  EXPECT_NE(o.code, 0);
  EXPECT_NE(o.text.find("grid.min"), std::string::npos) << o.text;
  o = cli("run " + kRadome + " --set grid.n_psi=0");
  EXPECT_NE(o.code, 0);
  EXPECT_NE(o.text.find("grid.n_psi"), std::string::npos) << o.text;
  o = cli("run " + kRadome + " --set markov.stay=0");
  EXPECT_NE(o.code, 0);
  EXPECT_NE(o.text.find("markov.stay"), std::string::npos) << o.text;
}

}  // namespace
