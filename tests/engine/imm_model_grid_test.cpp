// Issue 28: mode-parameter renewal (seed 001 eq. 4) of a model file's grid: the n-axis grid moves
// (engine/filter/imm_grid.h) equal the built-in radome's two-axis ones, and a run whose grid misses
// the true parameter finds it with Kp > 0 under every reading, and not with Kp = 0.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "core/scenario.h"
#include "filter/imm_grid.h"
#include "model/model_result.h"
#include "model/model_scenario.h"
#include "oracles/radome/radome_renewal.h"

namespace kfw {
namespace {

using nlohmann::json;

TEST(ImmModelGrid, MovesEqualTheBuiltInRadomes) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto [np, nt] : {std::pair{7, 7}, std::pair{5, 3}, std::pair{1, 4}, std::pair{2, 1}}) {
    std::vector<double> op, ot;
    for (int i = 0; i < np; ++i)
      op.push_back(np == 1 ? 0.0 : -0.05 + 0.1 * i / (np - 1));
    for (int i = 0; i < nt; ++i)
      ot.push_back(nt == 1 ? 0.0 : -0.03 + 0.06 * i / (nt - 1));
    VecX mu(np * nt);
    for (Eigen::Index j = 0; j < mu.size(); ++j)
      mu(j) = u(gen);
    mu /= mu.sum();
    for (auto [dp, dt] : {std::pair{0.004, -0.011}, std::pair{-0.2, 0.0}, std::pair{0.0, 0.05}}) {
      const VecX a = grid_remap(mu, {op, ot}, {dp, dt});
      const VecX b = radome::remap_probabilities(mu, op, ot, dp, dt);
      EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-15) << np << "×" << nt;
      EXPECT_NEAR(a.sum(), 1.0, 1e-14);
      const MatX T = grid_shift_transition({op, ot}, {dp, dt});
      const MatX R = radome::shift_transition(op, ot, dp, dt);
      EXPECT_LT((T - R).cwiseAbs().maxCoeff(), 1e-15) << np << "×" << nt;
      EXPECT_LT((T.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-14);
    }
  }
  // Three axes: remapping axis by axis equals the transition's transpose.
  const std::vector<std::vector<double>> off{{-1, 0, 1}, {-0.5, 0.5}, {-2, -1, 0, 1, 2}};
  VecX mu = VecX::LinSpaced(30, 1.0, 30.0);
  mu /= mu.sum();
  const std::vector<double> d{0.3, -0.2, 1.7};
  const VecX a = grid_remap(mu, off, d);
  const VecX b = grid_shift_transition(off, d).transpose() * mu;
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-15);
}

json grid_model(const char* reading) {
  auto L = [](std::initializer_list<nlohmann::detail::json_ref<json>> e) { return json::array(e); };
  auto P = [](double v, double lo, double hi) {
    return json{{"value", v}, {"min", lo}, {"max", hi}, {"scale", "linear"}};
  };
  json p = {{"format", "kfw-preset"}, {"version", 1}, {"scenario", "model"}};
  p["parameters"] = {{"q", P(0.5, 1e-3, 10)},
                     {"r", P(1.0, 1e-3, 10)},
                     {"sim.dt", P(0.1, 0.01, 1)},
                     {"sim.duration", P(100, 1, 1000)}};
  p["model"] = {{"version", 2},
                {"states", L({"x", "v"})},
                {"x0", L({"0", "0"})},
                {"P0", L({"10", "1"})},
                {"process",
                 {{"F", L({L({"1", "dt"}), L({"0", "1"})})},
                  {"Q", L({L({"dt^4/4*q^2", "dt^3/2*q^2"}), L({"dt^3/2*q^2", "dt^2*q^2"})})}}},
                {"measurements",
                 {{"pos", {{"roles", L({"z"})}, {"H", L({L({"1", "0"})})}, {"R", L({"r^2"})}}}}},
                {"modes",
                 {{"grid", L({{{"param", "r"}, {"min", 2.0}, {"max", 4.0}, {"n", 5}}})},
                  {"markov", {{"stay", 0.99}}},
                  {"renewal", {{"gain", 0.0}, {"start", 0.0}, {"mode", reading}}}}}};
  return p;
}

TEST(ImmModelGrid, RenewalFindsAParameterTheGridMisses) {
  // The data's r is 1 m; the grid starts on [2, 4] m.
  for (const char* reading : {"index", "slope", "rate", "mix"}) {
    auto s = make_model_scenario(grid_model(reading), "grid.json");
    ASSERT_TRUE(s.ok()) << s.error();
    for (int seed : {1, 2, 3}) {
      ParamValues v = (*s)->params().defaults();
      v["sim.seed"] = seed;
      auto d = (*s)->simulate(v);
      ASSERT_TRUE(d.ok());
      auto still = (*s)->run(*d, v);
      ASSERT_TRUE(still.ok()) << still.error();
      EXPECT_GT(still->get()->metrics.at("imm.r.final"), 1.95) << reading;
      const auto& r0 = dynamic_cast<const model::ModelResult&>(**still);
      EXPECT_EQ(r0.imm->axes[0].centre.front(), 3.0);
      EXPECT_EQ(r0.imm->axes[0].centre.back(), 3.0);
      v["Kp"] = 0.02;
      auto moved = (*s)->run(*d, v);
      ASSERT_TRUE(moved.ok()) << moved.error();
      EXPECT_NEAR(moved->get()->metrics.at("imm.r.final"), 1.0, 0.15) << reading << " " << seed;
      const auto& r1 = dynamic_cast<const model::ModelResult&>(**moved);
      EXPECT_LT(r1.imm->axes[0].centre.back(), 1.5) << reading;
      // Renewal that starts after the run's end is no renewal.
      v["renewal.start"] = 1e3;
      auto late = (*s)->run(*d, v);
      ASSERT_TRUE(late.ok());
      EXPECT_EQ(late->get()->metrics.at("imm.r.final"), still->get()->metrics.at("imm.r.final"));
    }
  }
}

// Equal ends with several values (a slider passing through equality): the run is valid and says
// that the grid cannot tell its values apart, naming the keys (as the built-in radome did).
TEST(ImmModelGrid, EqualEndsAreAWarningNamingTheKeys) {
  auto s = make_model_scenario(grid_model("index"), "grid.json");
  ASSERT_TRUE(s.ok()) << s.error();
  ParamValues v = (*s)->params().defaults();
  v["sim.duration"] = 5;
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok());
  v["grid.r.max"] = 2.0;
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& w = r->get()->warnings;
  const std::string want =
      "grid.r.min = grid.r.max = 2 with grid.r.n = 5: the 5 values of r are the same, so its "
      "estimate cannot move";
  EXPECT_NE(std::find(w.begin(), w.end(), want), w.end());
  v["grid.r.n"] = 1;  // one mode: nothing to tell apart, no warning
  auto one = (*s)->run(*d, v);
  ASSERT_TRUE(one.ok());
  EXPECT_TRUE(one->get()->warnings.empty());
}

TEST(ImmModelGrid, RenewalRefusals) {
  json p = grid_model("sideways");
  EXPECT_EQ(make_model_scenario(p, "g.json").error(),
            "g.json: model.modes.renewal.mode: 'sideways' is not a reading of renewal (index, "
            "slope, rate, mix)");
  p = grid_model("index");
  p["model"]["modes"]["list"] = json::array({{{"name", "a"}}, {{"name", "b"}}});
  p["model"]["modes"].erase("grid");
  EXPECT_EQ(make_model_scenario(p, "g.json").error(),
            "g.json: model.modes.renewal: renewal moves a grid: declare \"grid\"");
  p = grid_model("q");
  EXPECT_EQ(make_model_scenario(p, "g.json").error(),
            "g.json: model.modes.renewal.mode: 'q' is not a choice parameter");
}

}  // namespace
}  // namespace kfw
