// Issue 27: seed 000 as one model file (presets/helicopter.json: the built-in's
// parameter keys, sim.Ts as the simulation step, β and the closed forms as derived quantities,
// a world that simulates the hover sway, the bias walk and the dropouts) against the retired
// built-in `helicopter` scenario, now the oracle (tests/oracles/helicopter/). Equality in the form
// of ../shared/STAGE.md: |a − b| ≤ 1e-9 (|b| + σ_b), σ_b the oracle's posterior standard deviation
// of that state, or the column's largest magnitude for other columns.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/model_files.h"
#include "core/dataset.h"
#include "core/scenario.h"
#include "data/csv.h"
#include "document/workspace.h"
#include "model/model_result.h"
#include "oracles/helicopter/helicopter_oracle.h"

namespace kfw {
namespace world_helicopter_test {
namespace {

const std::string kFile = KFW_SOURCE_DIR "/presets/helicopter.json";
const std::string kLog = KFW_SHARED_DIR "/data/broad/10_undisturbed_slow_translation_A.csv";
constexpr double kTol = 1e-9;

// a (the model file) against b (the built-in), with the scale s per step (σ_b, or a constant).
::testing::AssertionResult same(const std::vector<double>& a, const std::vector<double>& b,
                                const std::vector<double>& s, const std::string& what) {
  if (a.size() != b.size()) {
    return ::testing::AssertionFailure() << what << ": sizes " << a.size() << " vs " << b.size();
  }
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (std::isnan(a[k]) && std::isnan(b[k])) continue;
    const double sk = s.size() == 1 ? s[0] : s[k];
    if (!(std::fabs(a[k] - b[k]) <= kTol * (std::fabs(b[k]) + sk))) {
      return ::testing::AssertionFailure()
             << what << " differs at step " << k << ": " << a[k] << " vs " << b[k];
    }
  }
  return ::testing::AssertionSuccess();
}

std::vector<double> largest(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) {
    if (std::isfinite(x)) m = std::max(m, std::fabs(x));
  }
  return {m};
}

std::vector<double> root(const std::vector<double>& v) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [](double x) { return std::sqrt(x); });
  return out;
}

// The oracle (the built-in's run) against the model file, both at the file's values `v`.
void expect_same_run(const Scenario& model, const Dataset& d, const ParamValues& v,
                     const std::string& label) {
  SCOPED_TRACE(label);
  const helicopter::HelicopterResult b = helicopter::run_with_metrics(d, v);
  auto rm = model.run(d, v);
  ASSERT_TRUE(rm.ok()) << rm.error();
  const auto& m = dynamic_cast<const model::ModelResult&>(**rm);
  EXPECT_TRUE(same(m.x[0], b.theta, root(b.P11), "theta"));
  EXPECT_TRUE(same(m.x[1], b.bias, root(b.P22), "bias"));
  EXPECT_TRUE(same(m.P[m.cov_index(0, 0)], b.P11, largest(b.P11), "P11"));
  EXPECT_TRUE(same(m.P[m.cov_index(0, 1)], b.P12, largest(b.P12), "P12"));
  EXPECT_TRUE(same(m.P[m.cov_index(1, 1)], b.P22, largest(b.P22), "P22"));
  ASSERT_EQ(m.chans.size(), 1u);
  EXPECT_TRUE(same(m.chans[0].y[0], b.innovation, largest(b.innovation), "innovation"));
  EXPECT_TRUE(same(m.chans[0].S[0], b.S, largest(b.S), "S"));
  EXPECT_EQ(m.chans[0].updates, b.updates);
  for (const char* key : {"rmse", "nis_mean", "nees_mean"}) {
    ASSERT_EQ(b.metrics.count(key), (*rm)->metrics.count(key)) << key;
    if (!b.metrics.count(key)) continue;
    const double x = b.metrics.at(key);
    EXPECT_NEAR((*rm)->metrics.at(key), x, kTol * std::fabs(x)) << key;
  }
}

// The issue's cases: m ∈ {1, 5}, γ ∈ {0, 0.003}, the other values as given.
void expect_same_runs(const Scenario& model, const Dataset& d, ParamValues v) {
  for (double m : {1.0, 5.0}) {
    for (double gamma : {0.0, 0.003}) {
      v["m"] = m;
      v["gamma"] = gamma;
      expect_same_run(model, d, v,
                      "m = " + std::to_string(m) + ", gamma = " + std::to_string(gamma));
    }
  }
}

// The seed presets keep their keys: every parameter of the version-2 presets saved at the fixtures'
// commit (tests/fixtures/preset_v2, when they named the built-in) is a parameter of the model file
// that replaced them, with the same value, range, unit and scale — all but `window`, the built-in
// view's NIS/NEES moving average, which the generic view does not have (CHANGES.md).
TEST(ModelWorldHelicopter, KeepsTheSeedPresetsParameterKeys) {
  for (const std::string name : {"helicopter", "broad_imu"}) {
    SCOPED_TRACE(name);
    std::ifstream old_in(KFW_SOURCE_DIR "/tests/fixtures/preset_v2/" + name + ".json");
    std::ifstream new_in(KFW_SOURCE_DIR "/presets/" + name + ".json");
    const auto old_preset = nlohmann::json::parse(old_in);
    const auto new_preset = nlohmann::json::parse(new_in);
    EXPECT_EQ(old_preset.at("scenario"), "helicopter");
    EXPECT_EQ(new_preset.at("scenario"), "model");
    EXPECT_EQ(std::filesystem::path(old_preset.value("data", "")).filename(),
              std::filesystem::path(new_preset.value("data", "")).filename());
    const auto& now = new_preset.at("parameters");
    for (const auto& [key, entry] : old_preset.at("parameters").items()) {
      if (key == "window") continue;  // the built-in view's NIS/NEES average (CHANGES.md)
      ASSERT_TRUE(now.contains(key)) << key;
      for (const char* field : {"value", "min", "max", "unit", "scale"}) {
        EXPECT_EQ(now.at(key).at(field), entry.at(field)) << key << "." << field;
      }
    }
  }
  auto model = testing::load_model_file(kFile);
  ASSERT_TRUE(model);
  EXPECT_FALSE(model->params().find("sim.dt"));  // sim.Ts is the simulation step
}

// presets/broad_imu.json itself: its data file, its mapping and its tuning.
TEST(ModelWorldHelicopter, SameEstimatesAsTheBuiltInOnTheRealLog) {
  if (!std::filesystem::exists(kLog)) GTEST_SKIP() << "no shared data at " << kLog;
  auto ws = open_workspace(KFW_SOURCE_DIR "/presets/broad_imu.json", {}, {});
  ASSERT_TRUE(ws.ok()) << ws.error();
  ASSERT_TRUE(ws->data_from_preset);
  auto data = load_dataset(*ws);
  ASSERT_TRUE(data.ok()) << data.error();
  EXPECT_EQ(ws->values.at("Q"), 256);  // the preset's tuning
  EXPECT_EQ(ws->values.at("R"), 4096);
  expect_same_runs(*ws->scenario, *data, ws->values);
}

TEST(ModelWorldHelicopter, SameEstimatesOnTheWorldsSimulation) {
  auto model = testing::load_model_file(kFile);
  ASSERT_TRUE(model);
  ParamValues v = model->params().defaults();
  v["sim.duration"] = 60;
  v["sim.angle_dropout"] = 0.1;
  v["sim.bias_walk"] = 0.2;
  auto d = model->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  expect_same_runs(*model, *d, v);
}

// β and the closed forms k1(β), p11⁻/N_θ as derived quantities equal the built-in's gain() (the
// oracle's, at the data's Ts = sim.Ts) and the DARE of the m-step model (γ = 0).
TEST(ModelWorldHelicopter, ClosedFormsEqualTheBuiltInAndTheDare) {
  auto model = testing::load_model_file(kFile);
  ASSERT_TRUE(model);
  ParamValues v = model->params().defaults();
  v["sim.duration"] = 5;
  auto d = model->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  for (double m : {1.0, 5.0, 25.0}) {
    for (double q : {1.0, 67.24, 5000.0}) {
      v["m"] = m;
      v["Q"] = q;
      auto r = model->run(*d, v);
      ASSERT_TRUE(r.ok()) << r.error();
      auto g = helicopter::gain_at(v, static_cast<int>(m), v.at("sim.Ts"));
      ASSERT_TRUE(g.ok()) << g.error();
      const Metrics& mm = (*r)->metrics;
      SCOPED_TRACE("m = " + std::to_string(m) + ", Q = " + std::to_string(q));
      EXPECT_NEAR(mm.at("derived.beta"), g->at("beta"), kTol * g->at("beta"));
      EXPECT_NEAR(mm.at("derived.k1"), g->at("k1"), kTol * g->at("k1"));
      EXPECT_NEAR(mm.at("derived.p11_over_R"), g->at("p11_over_R"), kTol * g->at("p11_over_R"));
      EXPECT_NEAR(mm.at("derived.k1"), g->at("k1_dare"), kTol * g->at("k1_dare"));
      EXPECT_NEAR(mm.at("derived.p11_over_R"), g->at("p11_over_R_dare"),
                  kTol * g->at("p11_over_R_dare"));
    }
  }
  // Seed 000's table (eq. 11; docs/reproductions.md, SpecTable/ClosedForm.MatchesSpecTable) on
  // the model file: Q chosen so that β = m Ts² Q / R takes the table's values.
  struct Row {
    double beta, k1, p11;
  };
  for (const Row& row : {Row{0.01, 0.0951, 0.1051}, Row{0.05, 0.2000, 0.2500},
                         Row{0.27, 0.4019, 0.6719}, Row{1.06, 0.6280, 1.6880}}) {
    for (double m : {1.0, 25.0}) {
      v["m"] = m;
      v["Q"] = row.beta * v.at("R") / (m * v.at("sim.Ts") * v.at("sim.Ts"));
      auto r = model->run(*d, v);
      ASSERT_TRUE(r.ok()) << r.error();
      const Metrics& mm = (*r)->metrics;
      SCOPED_TRACE("beta = " + std::to_string(row.beta) + ", m = " + std::to_string(m));
      EXPECT_NEAR(mm.at("derived.beta"), row.beta, 1e-9 * row.beta);
      EXPECT_NEAR(mm.at("derived.k1"), row.k1, 5e-5);
      EXPECT_NEAR(mm.at("derived.p11_over_R"), row.p11, 5e-5);
    }
  }
}

// The world draws the built-in simulator's streams in the same order (core/random.h): the same
// data to 1e-12 of each column's largest magnitude, seeds 1..20, with dropouts and a bias walk.
TEST(ModelWorldHelicopter, TheWorldSimulatesWhatTheBuiltInSimulates) {
  auto model = testing::load_model_file(kFile);
  ASSERT_TRUE(model);
  for (int seed = 1; seed <= 20; ++seed) {
    ParamValues v = model->params().defaults();
    v["sim.seed"] = seed;
    v["sim.duration"] = 60;
    v["sim.angle_dropout"] = 0.1;
    v["sim.bias_walk"] = 0.3;
    const Dataset db = helicopter::simulate(helicopter::sim_params(v));
    auto dm = model->simulate(v);
    ASSERT_TRUE(dm.ok()) << dm.error();
    ASSERT_EQ(dm->rows(), db.rows());
    for (const char* col : {"t", "gyro", "angle", "truth", "bias_truth"}) {
      ASSERT_TRUE(dm->has(col)) << col;
      const auto& b = db.col(col);
      EXPECT_TRUE(same(dm->col(col), b, {largest(b)[0] * 1e-3}, col))  // 1e-9 · 1e-3
          << "seed " << seed;
    }
  }
}

// "sim": {"dt": KEY} names a declared parameter, in a version-2 file.
TEST(ModelWorldHelicopter, TheSimulationStepKeyIsChecked) {
  std::ifstream in(kFile);
  auto j = nlohmann::ordered_json::parse(in);
  j["model"]["sim"]["dt"] = "sim.T";
  auto s = make_model_scenario(j, "h.json");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("h.json: model.sim.dt: unknown parameter 'sim.T' (did you mean"),
            std::string::npos)
      << s.error();
  j["model"]["sim"]["dt"] = "sim.Ts";
  j["model"]["version"] = 1;
  s = make_model_scenario(j, "h.json");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("a version-2 key"), std::string::npos) << s.error();
}

}  // namespace
}  // namespace world_helicopter_test
}  // namespace kfw
