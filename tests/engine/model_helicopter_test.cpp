// The seed-000 indirect KF declared as a model file (presets/models/helicopter_indirect.json)
// against the retired built-in `helicopter` scenario, now the oracle (tests/oracles/helicopter/):
// same estimates, covariances, innovations and metrics on the real IMU log and on the model's own
// simulation.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/model_files.h"
#include "core/dataset.h"
#include "core/scenario.h"
#include "data/csv.h"
#include "model/model_result.h"
#include "model/model_scenario.h"
#include "oracles/helicopter/helicopter_oracle.h"

namespace kfw {
namespace {

const std::string kPreset = KFW_SOURCE_DIR "/presets/models/helicopter_indirect.json";
const std::string kLog = KFW_SHARED_DIR "/data/broad/10_undisturbed_slow_translation_A.csv";

using testing::load_model_file;

// |a − b| ≤ max(1e-12, 1e-9 · max(|a|, |b|)), NaN equal to NaN.
::testing::AssertionResult close(const std::vector<double>& a, const std::vector<double>& b,
                                 const std::string& what) {
  if (a.size() != b.size()) {
    return ::testing::AssertionFailure() << what << ": sizes " << a.size() << " vs " << b.size();
  }
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (std::isnan(a[k]) && std::isnan(b[k])) continue;
    const double tol = std::max(1e-12, 1e-9 * std::max(std::fabs(a[k]), std::fabs(b[k])));
    if (!(std::fabs(a[k] - b[k]) <= tol)) {
      return ::testing::AssertionFailure()
             << what << " differs at step " << k << ": " << a[k] << " vs " << b[k]
             << " (difference " << a[k] - b[k] << ")";
    }
  }
  return ::testing::AssertionSuccess();
}

// The oracle (the built-in's run) against the model file, both at the model's values `v` (the
// oracle reads the keys the built-in's table shared with the file: Q, R, m, gamma, P0_*).
void expect_same_run(const Scenario& model, const Dataset& d, const ParamValues& v,
                     const std::string& label) {
  const helicopter::HelicopterResult b = helicopter::run_with_metrics(d, v);
  auto rm = model.run(d, v);
  ASSERT_TRUE(rm.ok()) << rm.error();
  const auto& m = dynamic_cast<const model::ModelResult&>(**rm);
  SCOPED_TRACE(label);
  EXPECT_TRUE(close(m.x[0], b.theta, "theta"));
  EXPECT_TRUE(close(m.x[1], b.bias, "bias"));
  EXPECT_TRUE(close(m.P[m.cov_index(0, 0)], b.P11, "P11"));
  EXPECT_TRUE(close(m.P[m.cov_index(0, 1)], b.P12, "P12"));
  EXPECT_TRUE(close(m.P[m.cov_index(1, 1)], b.P22, "P22"));
  ASSERT_EQ(m.chans.size(), 1u);
  EXPECT_TRUE(close(m.chans[0].y[0], b.innovation, "innovation"));
  EXPECT_TRUE(close(m.chans[0].S[0], b.S, "S"));
  EXPECT_TRUE(close(m.chans[0].nis, b.nis, "NIS"));
  EXPECT_TRUE(close(m.chans[0].K[0], b.k1, "k1"));
  EXPECT_TRUE(close(m.chans[0].K[1], b.k2, "k2"));
  EXPECT_EQ(m.chans[0].updates, b.updates);
  // The shared metrics agree too (same innovations, same NEES over θ).
  for (const char* key : {"rmse", "rmse.theta", "nis_mean", "nis_in_bounds", "nll", "whiteness_p",
                          "nees_mean", "nees_in_bounds"}) {
    ASSERT_EQ(b.metrics.count(key), (*rm)->metrics.count(key)) << key;
    if (!b.metrics.count(key)) continue;
    const double x = b.metrics.at(key), y = (*rm)->metrics.at(key);
    EXPECT_NEAR(y, x, std::max(1e-12, 1e-9 * std::fabs(x))) << key;
  }
}

TEST(ModelHelicopter, SameEstimatesAsTheBuiltInOnTheRealLog) {
  if (!std::filesystem::exists(kLog)) GTEST_SKIP() << "no shared data at " << kLog;
  auto data = read_csv(kLog);
  ASSERT_TRUE(data.ok()) << data.error();
  auto model = load_model_file(kPreset);
  ASSERT_TRUE(model);
  // presets/broad_imu.json's tuning.
  for (double m : {1.0, 5.0}) {
    for (double gamma : {0.0, 0.003}) {
      ParamValues v = model->params().defaults();
      v["Q"] = 256;
      v["R"] = 4096;
      v["m"] = m;
      v["gamma"] = gamma;
      expect_same_run(*model, *data, v,
                      "m = " + std::to_string(m) + ", gamma = " + std::to_string(gamma));
    }
  }
}

TEST(ModelHelicopter, SameEstimatesOnTheModelsOwnSimulationWithGaps) {
  auto model = load_model_file(kPreset);
  ASSERT_TRUE(model);
  ParamValues vm = model->params().defaults();
  vm["sim.duration"] = 30;
  auto d = model->simulate(vm);
  ASSERT_TRUE(d.ok()) << d.error();
  ASSERT_TRUE(d->has("gyro") && d->has("angle") && d->has("truth"));
  // Missing angle samples (no update) and a missing gyro sample (the last rate held).
  Dataset gaps = *d;
  auto& angle = gaps.columns[static_cast<std::size_t>(gaps.index("angle"))];
  for (std::size_t k = 3; k < angle.size(); k += 7)
    angle[k] = kNoSample;
  gaps.columns[static_cast<std::size_t>(gaps.index("gyro"))][50] = kNoSample;
  for (double m : {1.0, 3.0}) {
    vm["m"] = m;
    vm["gamma"] = 0.01;
    expect_same_run(*model, gaps, vm, "m = " + std::to_string(m));
  }
}

// The model's gain without data is at its simulation step sim.dt (20 ms), the built-in's at sim.Ts.
TEST(ModelHelicopter, SteadyStateGainEqualsTheBuiltInDare) {
  auto model = load_model_file(kPreset);
  ASSERT_TRUE(model);
  for (double m : {1.0, 5.0, 25.0}) {
    ParamValues vm = model->params().defaults();
    vm["m"] = m;
    auto gb = helicopter::gain_at(vm, static_cast<int>(m), vm.at("sim.dt"));
    auto gm = model->gain(vm);
    ASSERT_TRUE(gb.ok()) << gb.error();
    ASSERT_TRUE(gm.ok()) << gm.error();
    EXPECT_NEAR(gm->at("K.theta.angle"), gb->at("k1_dare"), 1e-9) << "m = " << m;
    EXPECT_NEAR(gm->at("K.bias.angle"), gb->at("k2_dare"), 1e-9) << "m = " << m;
    EXPECT_NEAR(gm->at("P_pred.theta") / vm["R"], gb->at("p11_over_R_dare"), 1e-8);
    EXPECT_EQ(gm->at("every"), m);
  }
}

TEST(ModelHelicopter, FilterIsAChoiceParameterAndAllThreeAgree) {
  auto model = load_model_file(kPreset);
  ASSERT_TRUE(model);
  const ParamSpec* f = model->params().find("filter");
  ASSERT_TRUE(f);
  EXPECT_EQ(f->scale, Scale::kChoice);
  // steady (issue 30): the fixed DARE gain, offered to a linear time-invariant one-channel model.
  EXPECT_EQ(f->choices, (std::vector<std::string>{"kf", "ekf", "ukf", "steady"}));
  ParamValues v = model->params().defaults();
  v["sim.duration"] = 10;
  auto d = model->simulate(v);
  ASSERT_TRUE(d.ok());
  std::vector<std::vector<double>> theta;
  for (const char* name : {"kf", "ekf", "ukf"}) {
    ASSERT_TRUE(model->params().apply_assignment(std::string("filter=") + name, v).ok());
    v["ukf.alpha"] = 1.0;
    v["ukf.beta"] = 0.0;
    v["ukf.kappa"] = 0.0;
    auto r = model->run(*d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    theta.push_back(dynamic_cast<const model::ModelResult&>(**r).x[0]);
  }
  for (std::size_t k = 0; k < theta[0].size(); ++k) {
    EXPECT_NEAR(theta[1][k], theta[0][k], 1e-12 * (1 + std::fabs(theta[0][k])));
    EXPECT_NEAR(theta[2][k], theta[0][k], 1e-9 * (1 + std::fabs(theta[0][k])));
  }
}

}  // namespace
}  // namespace kfw
