// The helicopter scenario end to end: simulator, indirect KF, metrics, bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/scenario.h"
#include "document/workspace.h"
#include "scenarios/helicopter/helicopter_model.h"
#include "scenarios/helicopter/helicopter_sim.h"
#include "scenarios/helicopter/indirect_kf.h"

namespace kfw {
namespace {

std::shared_ptr<const Scenario> heli() {
  auto s = make_scenario("helicopter");
  EXPECT_TRUE(s.ok());
  return std::shared_ptr<const Scenario>(std::move(*s));
}

TEST(HelicopterSim, SameSeedSameDataOtherSeedOtherData) {
  helicopter::SimParams p;
  p.duration_s = 5;
  const auto a = helicopter::simulate(p), b = helicopter::simulate(p);
  p.seed = 2;
  const auto c = helicopter::simulate(p);
  EXPECT_EQ(a.columns, b.columns);
  EXPECT_NE(a.col("gyro"), c.col("gyro"));
  EXPECT_EQ(a.rows(), 251u);
}

TEST(HelicopterSim, NoiseLevelsAreWhatWasAsked) {
  helicopter::SimParams p;
  p.duration_s = 400;
  const auto d = helicopter::simulate(p);
  double se = 0;
  const auto& angle = d.col("angle");
  const auto& truth = d.col("truth");
  for (std::size_t i = 0; i < d.rows(); ++i)
    se += (angle[i] - truth[i]) * (angle[i] - truth[i]);
  EXPECT_NEAR(std::sqrt(se / d.rows()), p.sigma_angle, 0.03 * p.sigma_angle);
}

TEST(HelicopterScenario, MultiRateUpdatesEveryMthSample) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.duration"] = 20;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok());
  const std::size_t n = d->rows();
  for (int m : {1, 5, 25, 100}) {
    v["m"] = m;
    auto r = s->run(*d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    const auto& h = dynamic_cast<const helicopter::HelicopterResult&>(**r);
    EXPECT_EQ(h.updates, (n + m - 1) / m) << "m = " << m;
    for (std::size_t k = 0; k < n; ++k) {
      EXPECT_EQ(std::isfinite(h.k1[k]), k % m == 0) << "k = " << k << " m = " << m;
    }
  }
}

TEST(HelicopterScenario, FilterBeatsSensorAndGainReachesDare) {
  auto s = heli();
  auto v = s->params().defaults();
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok());
  for (int m : {1, 5, 25}) {
    v["m"] = m;
    auto r = s->run(*d, v);
    ASSERT_TRUE(r.ok());
    const auto& met = (*r)->metrics;
    // Every sample an update: far better than the sensor; sparser updates still better.
    EXPECT_LT(met.at("rmse"), (m == 1 ? 0.5 : 1.0) * met.at("rmse_sensor")) << "m = " << m;
    EXPECT_NEAR(met.at("k1_final"), met.at("k1_steady"), 0.02 * met.at("k1_steady")) << "m = " << m;
    EXPECT_NEAR(met.at("k1_steady"), met.at("k1_closed_form"), 1e-8);
    // Tuned to the simulator's true noise, the innovations are consistent.
    EXPECT_NEAR(met.at("nis_mean"), 1.0, 0.15) << "m = " << m;
  }
}

TEST(HelicopterScenario, GammaTracksADriftingBias) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.bias_walk"] = 0.3;
  v["sim.duration"] = 300;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok());
  auto r0 = s->run(*d, v);
  v["gamma"] = 0.006;
  auto r1 = s->run(*d, v);
  ASSERT_TRUE(r0.ok() && r1.ok());
  EXPECT_LT((*r1)->metrics.at("rmse.bias"), (*r0)->metrics.at("rmse.bias"));
}

TEST(HelicopterScenario, MissingAngleSamplesSkipTheUpdate) {
  auto s = heli();
  auto v = s->params().defaults();
  v["sim.angle_dropout"] = 0.5;
  v["sim.duration"] = 30;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok());
  auto r = s->run(*d, v);
  ASSERT_TRUE(r.ok());
  const auto& h = dynamic_cast<const helicopter::HelicopterResult&>(**r);
  std::size_t present = 0;
  for (double a : d->col("angle"))
    present += std::isfinite(a);
  EXPECT_EQ(h.updates, present);
  EXPECT_LT(present, d->rows());
}

TEST(HelicopterScenario, BadInputIsAnErrorNamingTheProblem) {
  auto s = heli();
  auto v = s->params().defaults();
  Dataset d;
  d.source = "x.csv";
  d.add("t", 3);
  d.add("gyro", 3);
  auto r = s->run(d, v);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("x.csv: missing required column 'angle'"), std::string::npos);
  v["R"] = -1;
  auto d2 = s->simulate(s->params().defaults());
  auto r2 = s->run(*d2, v);
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.error().find("'R'"), std::string::npos);
}

// The real BROAD log (shared/data): the README's reference figures, and a tuned filter beats both
// sensors several times over.
TEST(HelicopterScenario, RealImuLog) {
  const std::string path =
      std::string(KFW_SHARED_DIR) + "/data/broad/10_undisturbed_slow_translation_A.csv";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not present: " << path;
  auto s = heli();
  auto d = load_dataset_file(*s, path);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_NEAR(d->median_dt(), 0.0035, 1e-6);
  auto v = s->params().defaults();
  v["Q"] = 256;
  v["R"] = 4096;
  auto r0 = s->run(*d, v);
  v["gamma"] = 0.003;
  auto r = s->run(*d, v);
  ASSERT_TRUE(r.ok() && r0.ok());
  EXPECT_NEAR((*r)->metrics.at("rmse_sensor"), 7.74, 0.01);
  EXPECT_LT((*r0)->metrics.at("rmse"), 7.74 / 3);
  // The slowly varying bias model does better still (data/broad/README.md).
  EXPECT_LT((*r)->metrics.at("rmse"), 0.8 * (*r0)->metrics.at("rmse"));
}

}  // namespace
}  // namespace kfw
