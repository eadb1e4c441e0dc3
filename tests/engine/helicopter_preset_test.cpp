// Seed 000 end to end on its model file (presets/helicopter.json; the real log through
// presets/broad_imu.json): multi-rate updates, the filter against the sensor and the DARE gain,
// the slowly varying bias, missing samples, bad input. Until issue 30 these ran through the
// built-in `helicopter` scenario (HelicopterScenario.*), with the same keys and thresholds.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/scenario.h"
#include "core/statistics.h"
#include "document/preset.h"
#include "document/workspace.h"
#include "model/model_result.h"

namespace kfw {
namespace {

struct HeliPreset {
  std::shared_ptr<const Scenario> s;
  ParamValues values;
};

HeliPreset heli_preset() {
  auto p = load_preset(KFW_SOURCE_DIR "/presets/helicopter.json");
  EXPECT_TRUE(p.ok()) << p.error();
  if (!p.ok()) return {};
  return {p->instance, p->values};
}

const model::ModelResult& heli_model(const std::shared_ptr<const RunResult>& r) {
  return dynamic_cast<const model::ModelResult&>(*r);
}

// The angle sensor's RMSE against truth: what the filter has to beat (the built-in's
// `rmse_sensor`).
double heli_sensor_rmse(const Dataset& d) {
  return rmse_finite(d.col("angle"), d.col("truth"));
}

TEST(HelicopterPreset, MultiRateUpdatesEveryMthSample) {
  auto [s, v] = heli_preset();
  ASSERT_TRUE(s);
  v["sim.duration"] = 20;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  const std::size_t n = d->rows();
  for (int m : {1, 5, 25, 100}) {
    v["m"] = m;
    auto r = s->run(*d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    const auto& h = heli_model(*r);
    ASSERT_EQ(h.chans.size(), 1u);
    EXPECT_EQ(h.chans[0].updates, (n + m - 1) / m) << "m = " << m;
    const auto& k1 = h.chans[0].K[0];  // K.theta.angle
    ASSERT_EQ(k1.size(), n);
    for (std::size_t k = 0; k < n; ++k) {
      EXPECT_EQ(std::isfinite(k1[k]), k % m == 0) << "k = " << k << " m = " << m;
    }
  }
}

TEST(HelicopterPreset, FilterBeatsSensorAndGainReachesDare) {
  auto [s, v] = heli_preset();
  ASSERT_TRUE(s);
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  const double sensor = heli_sensor_rmse(*d);
  for (int m : {1, 5, 25}) {
    v["m"] = m;
    auto r = s->run(*d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    auto g = s->gain(v, &*d);
    ASSERT_TRUE(g.ok()) << g.error();
    const auto& met = (*r)->metrics;
    // Every sample an update: far better than the sensor; sparser updates still better.
    EXPECT_LT(met.at("rmse"), (m == 1 ? 0.5 : 1.0) * sensor) << "m = " << m;
    // The last update's gain is the DARE's; the DARE's is the closed form k1(β) (γ = 0).
    const double k1_final = last_finite(heli_model(*r).chans[0].K[0]);
    const double k1_steady = g->at("K.theta.angle");
    EXPECT_NEAR(k1_final, k1_steady, 0.02 * k1_steady) << "m = " << m;
    EXPECT_NEAR(k1_steady, met.at("derived.k1"), 1e-8);
    // Tuned to the simulator's true noise, the innovations are consistent.
    EXPECT_NEAR(met.at("nis_mean"), 1.0, 0.15) << "m = " << m;
  }
}

TEST(HelicopterPreset, GammaTracksADriftingBias) {
  auto [s, v] = heli_preset();
  ASSERT_TRUE(s);
  v["sim.bias_walk"] = 0.3;
  v["sim.duration"] = 300;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r0 = s->run(*d, v);
  v["gamma"] = 0.006;
  auto r1 = s->run(*d, v);
  ASSERT_TRUE(r0.ok() && r1.ok());
  EXPECT_LT((*r1)->metrics.at("rmse.bias"), (*r0)->metrics.at("rmse.bias"));
}

TEST(HelicopterPreset, MissingAngleSamplesSkipTheUpdate) {
  auto [s, v] = heli_preset();
  ASSERT_TRUE(s);
  v["sim.angle_dropout"] = 0.5;
  v["sim.duration"] = 30;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = s->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  std::size_t present = 0;
  for (double a : d->col("angle"))
    present += std::isfinite(a);
  EXPECT_EQ(heli_model(*r).chans[0].updates, present);
  EXPECT_LT(present, d->rows());
}

TEST(HelicopterPreset, BadInputIsAnErrorNamingTheProblem) {
  auto [s, v] = heli_preset();
  ASSERT_TRUE(s);
  Dataset d;
  d.source = "x.csv";
  d.add("t", 3);
  d.add("gyro", 3);
  auto r = s->run(d, v);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("x.csv: missing required column 'angle'"), std::string::npos)
      << r.error();
  auto d2 = s->simulate(v);
  ASSERT_TRUE(d2.ok()) << d2.error();
  v["R"] = -1;
  auto r2 = s->run(*d2, v);
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.error().find("'R'"), std::string::npos) << r2.error();
}

// The real BROAD log (shared/data) through presets/broad_imu.json: the README's reference
// figures, and a tuned filter beats the sensor several times over.
TEST(HelicopterPreset, RealImuLog) {
  const std::string path =
      std::string(KFW_SHARED_DIR) + "/data/broad/10_undisturbed_slow_translation_A.csv";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not present: " << path;
  auto ws = open_workspace(KFW_SOURCE_DIR "/presets/broad_imu.json", {}, {});
  ASSERT_TRUE(ws.ok()) << ws.error();
  auto d = load_dataset(*ws);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_NEAR(d->median_dt(), 0.0035, 1e-6);
  EXPECT_NEAR(heli_sensor_rmse(*d), 7.74, 0.01);
  auto v = ws->values;
  v["Q"] = 256;
  v["R"] = 4096;
  v["gamma"] = 0.0;
  auto r0 = ws->scenario->run(*d, v);
  v["gamma"] = 0.003;
  auto r = ws->scenario->run(*d, v);
  ASSERT_TRUE(r.ok() && r0.ok());
  EXPECT_LT((*r0)->metrics.at("rmse"), 7.74 / 3);
  // The slowly varying bias model does better still (data/broad/README.md).
  EXPECT_LT((*r)->metrics.at("rmse"), 0.8 * (*r0)->metrics.at("rmse"));
}

}  // namespace
}  // namespace kfw
