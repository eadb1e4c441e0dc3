// Gain curves of any scenario (experiment/gain_curve.h): on the 1-D constant-velocity model file
// every point is the closed-form α-β filter of seed 003 at its tracking index, the operating point
// is the DARE gain at the live values, and a model without a steady state says so.
#include "experiment/gain_curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/model_files.h"
#include "model/model_scenario.h"
#include "oracles/ballbeam/alpha_beta.h"

namespace kfw {
namespace {

using testing::load_model;

TEST(GainCurve, ConstantVelocityCurveIsTheAlphaBetaCurve) {
  auto s = load_model("cv1d.json");
  ASSERT_TRUE(s);
  const ParamValues v = s->params().defaults();
  auto c = gain_curve(*s, v, "sigma_a", 41);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_TRUE(c->log);
  ASSERT_EQ(c->x.size(), 41u);
  EXPECT_DOUBLE_EQ(c->x.front(), s->params().find("sigma_a")->min);
  EXPECT_NEAR(c->x.back(), s->params().find("sigma_a")->max, 1e-9);
  ASSERT_EQ(c->entries, (std::vector<std::string>{"K.v.z", "K.x.z"}));
  const double T = v.at("sim.dt"), sigma_r = v.at("sigma_r");
  int checked = 0;
  for (std::size_t i = 0; i < c->x.size(); ++i) {
    const double lambda = c->x[i] * T * T / sigma_r;
    if (lambda > 1e4) continue;  // the closed form loses digits where α → 1
    const auto ab = ballbeam::alpha_beta(lambda);
    EXPECT_NEAR(c->values[1][i], ab.alpha, 1e-9) << "λ = " << lambda;
    EXPECT_NEAR(c->values[0][i] * T, ab.beta, 1e-9) << "λ = " << lambda;
    ++checked;
  }
  EXPECT_GT(checked, 30);
  // The operating point: the DARE gain at the live values.
  auto g = s->gain(v);
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(c->at_x, v.at("sigma_a"));
  EXPECT_EQ(c->at[0], g->at("K.v.z"));
  EXPECT_EQ(c->at[1], g->at("K.x.z"));
  EXPECT_TRUE(c->steady.count("P_post.x"));
}

TEST(GainCurve, LinearParameterIsSpacedEvenlyAndSimulatorSettingsAreNotOffered) {
  auto s = load_model("helicopter_indirect.json");
  ASSERT_TRUE(s);
  const auto keys = gain_curve_parameters(*s);
  ASSERT_FALSE(keys.empty());
  for (const auto& k : keys) {
    EXPECT_NE(k.rfind("sim.", 0), 0u) << k;  // simulator settings are not filter parameters
    EXPECT_NE(k, "filter");
    EXPECT_NE(k, "m");  // an integer: no curve
  }
  auto c = gain_curve(*s, s->params().defaults(), "gamma", 11);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_FALSE(c->log);
  for (std::size_t i = 1; i < c->x.size(); ++i)
    EXPECT_NEAR(c->x[i] - c->x[i - 1], 0.01, 1e-15);
  for (const auto& e : c->values) {
    for (double k : e)
      EXPECT_TRUE(std::isfinite(k));
  }
}

// The first curve shown follows a parameter that moves the gain: σ_a, not an initial variance.
TEST(GainCurve, DefaultParameterMovesTheGain) {
  auto s = load_model("cv1d.json");
  ASSERT_TRUE(s);
  EXPECT_EQ(default_gain_curve_parameter(*s, s->params().defaults()), "sigma_a");
  auto h = load_model("helicopter_indirect.json");
  ASSERT_TRUE(h);
  EXPECT_EQ(default_gain_curve_parameter(*h, h->params().defaults()), "Q");
  auto rb = load_model("range_bearing.json");
  ASSERT_TRUE(rb);
  EXPECT_EQ(default_gain_curve_parameter(*rb, rb->params().defaults()), "");
}

TEST(GainCurve, ModelWithoutSteadyStateSaysWhy) {
  auto s = load_model("range_bearing.json");
  ASSERT_TRUE(s);
  const auto keys = gain_curve_parameters(*s);
  ASSERT_FALSE(keys.empty());
  auto c = gain_curve(*s, s->params().defaults(), keys.front());
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().find("not linear time-invariant"), std::string::npos) << c.error();
}

TEST(GainCurve, UnknownOrDiscreteParameterIsRefused) {
  auto s = load_model("cv1d.json");
  ASSERT_TRUE(s);
  EXPECT_FALSE(gain_curve(*s, s->params().defaults(), "nope").ok());
  EXPECT_FALSE(gain_curve(*s, s->params().defaults(), "sim.seed").ok());
  EXPECT_FALSE(gain_curve(*s, s->params().defaults(), "filter").ok());
}

}  // namespace
}  // namespace kfw
