// Issue 27: channel groups (stacked / sequential instants, a choice parameter's alternatives),
// the distance gate and input ages (engine/model/model_groups.cpp, model_filter_detail.h) — seed
// 004's AS / SC / SI as a model file (presets/underwater.json) against the retired built-in's
// underwater EKF, now the oracle tests/oracles/underwater (issue 30), on the same simulated data
// (the world's data equal the oracle simulator's to 1e-12, model_world_underwater_test.cpp), in
// the equality form of ../shared/STAGE.md with tol 1e-9.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "common/model_files.h"
#include "core/dataset.h"
#include "core/scenario.h"
#include "model/model_result.h"
#include "model/model_scenario.h"
#include "model/plots/model_plots.h"
#include "oracles/underwater/underwater_ekf.h"
#include "oracles/underwater/underwater_params.h"
#include "oracles/underwater/underwater_sim.h"
#include "oracles/underwater/underwater_stats.h"

namespace kfw {
namespace model_groups_test {
namespace {

const std::string kFile = KFW_SOURCE_DIR "/presets/underwater.json";
const char* const kSchemes[] = {"AS", "SC", "SI"};

double largest(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) {
    if (std::isfinite(x)) m = std::max(m, std::fabs(x));
  }
  return m;
}

// |a − b| ≤ tol·(|b| + σ) row by row, NaN where the other is NaN; σ per row or the column's
// largest magnitude (sigma null).
::testing::AssertionResult close(const std::string& what, const std::vector<double>& a,
                                 const std::vector<double>& b, const std::vector<double>* sigma,
                                 double tol) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << what << ": sizes differ";
  const double scale = largest(b);
  for (std::size_t k = 0; k < b.size(); ++k) {
    if (std::isnan(a[k]) != std::isnan(b[k])) {
      return ::testing::AssertionFailure()
             << what << " row " << k << ": " << a[k] << " vs " << b[k];
    }
    if (std::isnan(b[k])) continue;
    const double s = sigma ? std::sqrt((*sigma)[k]) : scale;
    if (!(std::fabs(a[k] - b[k]) <= tol * ((sigma ? std::fabs(b[k]) : 0.0) + s))) {
      return ::testing::AssertionFailure()
             << what << " row " << k << ": " << a[k] << " vs " << b[k];
    }
  }
  return ::testing::AssertionSuccess();
}

// The model file; the built-in it replaced is the oracle, fed the same values (its keys).
std::unique_ptr<Scenario> load() {
  return testing::load_model_file(kFile);
}

// The index of a choice parameter's label.
double choice(const Scenario& s, const std::string& key, const std::string& label) {
  const auto& choices = s.params().find(key)->choices;
  const auto at = std::find(choices.begin(), choices.end(), label);
  EXPECT_NE(at, choices.end()) << key << " " << label;
  return static_cast<double>(at - choices.begin());
}

ParamValues values(const Scenario& s, int seed, const char* scheme) {
  ParamValues v = s.params().defaults();
  v["sim.seed"] = seed;
  v["sim.duration"] = 60;
  v["sim.range_dropout"] = 0.1;
  v["scheme"] = choice(s, "scheme", scheme);
  return v;
}

// Runs the oracle EKF and the model file on the oracle's simulated data; the tables, and the rmse
// of each.
struct Runs {
  Dataset b, m;
  double rmse_b = 0.0, rmse_m = 0.0;
};

Runs run_both(const Scenario& model, int seed, const char* scheme) {
  Runs out;
  const ParamValues v = values(model, seed, scheme);
  const Dataset data = underwater::simulate(underwater::sim_params(v));
  auto rb = underwater::run_ekf(data, underwater::filter_params(v));
  auto rm = model.run(data, v);
  EXPECT_TRUE(rb.ok()) << rb.error();
  EXPECT_TRUE(rm.ok()) << rm.error();
  if (!rb.ok() || !rm.ok()) return out;
  out.b = rb->table();
  out.m = (*rm)->table();
  out.rmse_b = underwater::position_rmse(*rb);
  out.rmse_m = (*rm)->metrics.at("rmse");
  return out;
}

// Estimates, covariances, innovations and S per range, and which ranges the gate rejected.
TEST(ModelGroups, UnderwaterSchemesEqualTheBuiltInEkf) {
  const auto s = load();
  ASSERT_TRUE(s);
  for (int seed = 1; seed <= 3; ++seed) {
    for (const char* scheme : kSchemes) {
      SCOPED_TRACE(std::string(scheme) + " seed " + std::to_string(seed));
      const Runs r = run_both(*s, seed, scheme);
      ASSERT_GT(r.b.rows(), 0u);
      for (const char* c : {"x", "y", "z"}) {
        const std::string sc(c);
        EXPECT_TRUE(close(sc, r.m.col("x." + sc), r.b.col(sc), &r.b.col("P" + sc + sc), 1e-9));
      }
      for (const auto& [m, b] : {std::pair{"P.x", "Pxx"},
                                 {"P.y", "Pyy"},
                                 {"P.z", "Pzz"},
                                 {"P.x.y", "Pxy"},
                                 {"P.x.z", "Pxz"},
                                 {"P.y.z", "Pyz"}}) {
        EXPECT_TRUE(close(m, r.m.col(m), r.b.col(b), nullptr, 1e-9));
      }
      std::size_t gated = 0;
      for (int i = 1; i <= 4; ++i) {
        const std::string n = std::to_string(i);
        EXPECT_TRUE(
            close("y" + n, r.m.col("y.range" + n), r.b.col("innovation" + n), nullptr, 1e-9));
        EXPECT_TRUE(close("S" + n, r.m.col("S.range" + n), r.b.col("S" + n), nullptr, 1e-9));
        const auto& status = r.b.col("status_range" + n);
        const auto& y = r.m.col("y.range" + n);
        const auto& nis = r.m.col("nis.range" + n);
        for (std::size_t k = 0; k < status.size(); ++k) {
          const bool rejected = status[k] == 1.0;
          gated += rejected ? 1 : 0;
          ASSERT_EQ(rejected, std::isfinite(y[k]) && std::isnan(nis[k]))
              << "range " << n << " row " << k;
        }
      }
      EXPECT_GT(gated, 50u);  // the outliers (≈ 90 in 60 s) and some false alarms
      EXPECT_NEAR(r.rmse_m, r.rmse_b, 1e-9 * r.rmse_b);
    }
  }
}

// Seed 004's claim that the stacked update with the full R wins: in as many of seeds 1..10 as
// with the built-in's EKF (measured on the built-in first: SC best in 5 of 10 at 60 s, dropout
// 0.1).
TEST(ModelGroups, StackedIsBestInAsManySeedsAsWithTheBuiltIn) {
  const auto s = load();
  ASSERT_TRUE(s);
  int best_b = 0, best_m = 0;
  for (int seed = 1; seed <= 10; ++seed) {
    double b[3], m[3];
    for (int i = 0; i < 3; ++i) {
      const Runs r = run_both(*s, seed, kSchemes[i]);
      b[i] = r.rmse_b;
      m[i] = r.rmse_m;
    }
    best_b += b[1] < b[0] && b[1] < b[2] ? 1 : 0;
    best_m += m[1] < m[0] && m[1] < m[2] ? 1 : 0;
  }
  EXPECT_EQ(best_m, best_b);
}

// Seed 004, Table 14: the outliers the gate catches and its false alarms, per seed, as with the
// built-in's EKF (the paper's 3 minutes, 276 outliers, each scheme).
TEST(ModelGroups, OutliersDetectedAndFalseAlarmsPerSeedAsTheBuiltIns) {
  const auto s = load();
  ASSERT_TRUE(s);
  for (int seed = 1; seed <= 10; ++seed) {
    for (const char* scheme : kSchemes) {
      SCOPED_TRACE(std::string(scheme) + " seed " + std::to_string(seed));
      ParamValues v = values(*s, seed, scheme);
      v["sim.duration"] = 180;
      v["sim.range_dropout"] = 0;
      const Dataset data = underwater::simulate(underwater::sim_params(v));
      auto rb = underwater::run_ekf(data, underwater::filter_params(v));
      auto rm = s->run(data, v);
      ASSERT_TRUE(rb.ok() && rm.ok());
      ASSERT_TRUE(rb->outliers_known);
      const Metrics& m = (*rm)->metrics;
      EXPECT_EQ(m.at("outliers_injected"), static_cast<double>(rb->outliers_injected));
      EXPECT_EQ(m.at("outliers_detected"), static_cast<double>(rb->outliers_detected));
      EXPECT_EQ(m.at("outliers_false_alarm"), static_cast<double>(rb->outliers_false_alarm));
      EXPECT_EQ((*rm)->metrics.at("outliers_injected"), 276.0);
      EXPECT_GE((*rm)->metrics.at("outliers_detected"), 0.94 * 276);
    }
  }
}

// Seed 004, eqs. 5–8: the world's range errors have the covariance σ_r² I + σ_c² 1 1ᵀ and the
// depth error σ_d², measured as the built-in's statistics measure them (20 min, no outliers); and
// equal to the statistics of the oracle simulator's data (the retired built-in's).
TEST(ModelGroups, TheWorldsRangeErrorsReproduceEquations5To8) {
  const auto s = load();
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  v["sim.seed"] = 11;
  v["sim.duration"] = 1200;
  v["sim.outliers"] = 0;
  auto data = s->simulate(v);
  ASSERT_TRUE(data.ok()) << data.error();
  const auto st = underwater::error_stats(*data);
  ASSERT_TRUE(st) << st.error();
  ASSERT_GT(st->instants, 5000u);
  const auto design = underwater::design_covariance(v.at("sim.sigma_range"), v.at("sim.sigma_corr"),
                                                    v.at("sim.sigma_depth"));
  // 1200 draws of n_c (t_gap 1 s): its variance within ±4 % (1σ), so 15 % is ≈ 3.5σ.
  for (int i = 0; i < underwater::kErrorDims; ++i) {
    for (int j = 0; j < underwater::kErrorDims; ++j) {
      const double want = design(i, j);
      EXPECT_NEAR(st->covariance(i, j), want, want != 0.0 ? 0.15 * want : 0.004)
          << "(" << i << ", " << j << ")";
    }
  }
  const Dataset same = underwater::simulate(underwater::sim_params(v));
  const auto sb = underwater::error_stats(same);
  ASSERT_TRUE(sb);
  EXPECT_LE((st->covariance - sb->covariance).cwiseAbs().maxCoeff(), 1e-9);
}

// The same statistics declared in the file: derived series of the measurements minus the truth
// (range1 − |B1 − X|, …, depth − z) and a covariance block at synchronous instants that leaves
// out an instant holding a marked outlier — equal to the built-in's statistics on the same data
// (the default 3 minutes with 276 outliers, three seeds).
TEST(ModelGroups, TheFilesErrorCovarianceBlockIsTheBuiltInsStatistics) {
  auto m = testing::load_model_file(kFile);
  ASSERT_TRUE(m);
  const auto layout = model_layout_of(*m);
  ASSERT_TRUE(layout);
  const model::PlotBlockSpec* block = nullptr;
  for (const auto& b : layout->plots) {
    if (b.id == "covariance") block = &b;
  }
  ASSERT_NE(block, nullptr);
  for (int seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    ParamValues v = m->params().defaults();
    v["sim.seed"] = seed;
    auto d = m->simulate(v);
    ASSERT_TRUE(d.ok()) << d.error();
    auto r = m->run(*d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    const auto c =
        model::covariance_block_data(*block, dynamic_cast<const model::ModelResult&>(**r));
    const auto st = underwater::error_stats(*d);
    ASSERT_TRUE(st) << st.error();
    ASSERT_EQ(c.n, 5u);
    EXPECT_EQ(c.count, st->instants);
    EXPECT_EQ(c.excluded, st->outlier_instants);
    EXPECT_GT(c.excluded, 100u);
    for (int i = 0; i < 5; ++i) {
      for (int j = 0; j < 5; ++j) {
        EXPECT_NEAR(c.sample[static_cast<std::size_t>(i * 5 + j)], st->covariance(i, j), 1e-12)
            << i << ", " << j;
      }
    }
  }
}

// A channel whose outlier column is missing from the data is left out of the outlier counts with
// a warning naming it; with none of the columns the counts are undefined, not zero.
TEST(ModelGroups, MissingOutlierColumnsAreNamedNotCountedAsZero) {
  auto m = testing::load_model_file(kFile);
  ASSERT_TRUE(m);
  ParamValues v = values(*m, 4, "SC");
  auto d = m->simulate(v);
  ASSERT_TRUE(d.ok());
  auto without = [&](const std::vector<std::string>& drop) {
    Dataset out;
    for (std::size_t c = 0; c < d->names.size(); ++c) {
      if (std::find(drop.begin(), drop.end(), d->names[c]) != drop.end()) continue;
      out.names.push_back(d->names[c]);
      out.columns.push_back(d->columns[c]);
    }
    return out;
  };
  auto all = m->run(*d, v);
  auto some = m->run(without({"outlier1"}), v);
  auto none = m->run(without({"outlier1", "outlier2", "outlier3", "outlier4"}), v);
  ASSERT_TRUE(all.ok() && some.ok() && none.ok());
  EXPECT_LT((*some)->metrics.at("outliers_injected"), (*all)->metrics.at("outliers_injected"));
  const auto& w = (*some)->warnings;
  EXPECT_TRUE(std::any_of(w.begin(), w.end(), [](const std::string& x) {
    return x.find("channel 'range1': its outlier column 'outlier1' is not in the data") !=
           std::string::npos;
  }));
  EXPECT_EQ((*none)->metrics.count("outliers_injected"), 0u);
  EXPECT_EQ((*none)->undefined.count("outliers_detected"), 1u);
}

nlohmann::json underwater_json() {
  std::ifstream in(kFile);
  return nlohmann::json::parse(in);
}

std::string load_error(const nlohmann::json& j) {
  auto s = make_model_scenario(j, "uw.json");
  return s.ok() ? std::string("(loaded)") : s.error();
}

// Each mistake in a group, a distance gate or an input's age is refused at load, naming the key.
TEST(ModelGroups, BadGroupsGatesAndAgesAreRefusedWithTheirKey) {
  struct Case {
    std::function<void(nlohmann::json&)> edit;
    std::string want;
  };
  const std::vector<Case> cases = {
      {[](auto& m) { m["groups"]["ranges"]["channels"][1] = "rnage2"; },
       "uw.json: model.groups.ranges.channels[1]: unknown channel 'rnage2' (did you mean "
       "'range2'?)"},
      {[](auto& m) { m["groups"]["ranges"]["channels"][1] = "range1"; },
       "uw.json: model.groups.ranges.channels[1]: channel 'range1' is already in a group"},
      {[](auto& m) {
         m["measurements"]["range2"]["roles"].push_back("extra");
         m["measurements"]["range2"]["h"].push_back("x");
         m["measurements"]["range2"]["R"].push_back("1");
         m["measurements"]["range2"].erase("gate");
       },
       "uw.json: model.groups.ranges.channels[1]: channel 'range2' has 2 components; a group's "
       "members are scalar channels"},
      {[](auto& m) { m["groups"]["ranges"]["scheme"].erase("SI"); },
       "uw.json: model.groups.ranges.scheme: missing the alternative for 'scheme' = 'SI'"},
      {[](auto& m) { m["groups"]["ranges"]["scheme"]["SX"] = "each"; },
       "uw.json: model.groups.ranges.scheme.SX: unknown choice of 'scheme' 'SX' (did you mean "
       "'SC'?)"},
      {[](auto& m) { m["groups"]["ranges"]["scheme"]["SC"] = "stack"; },
       "uw.json: model.groups.ranges.scheme.SC: expected \"each\", \"stacked\" or "
       "\"sequential\", got \"stack\""},
      {[](auto& m) { m["groups"]["ranges"]["scheme"]["param"] = "gate"; },
       "uw.json: model.groups.ranges.scheme.param: unknown choice parameter 'gate'"},
      {[](auto& m) { m["groups"]["ranges"]["cross"] = "x"; },
       "uw.json: model.groups.ranges.cross: "},
      {[](auto& m) { m["groups"]["ranges"]["cross"] = "1"; },
       "uw.json: model.groups.ranges.cross: the stacked R (members' R on the diagonal, cross 1 "
       "elsewhere) is not positive semidefinite"},
      {[](auto& m) {
         m["measurements"]["depth"]["gate"] = {{"sigma", "-1"}};
       },
       "uw.json: model.measurements.depth.gate.sigma: -1 at the parameters' values; expected a "
       "distance > 0"},
      {[](auto& m) { m["inputs"][1]["age"] = "psi_age"; },
       "uw.json: model.inputs[5].age: 'psi_age' is already a symbol"},
      {[](auto& m) { m["plots"][2]["exclude"]["e_r1"] = "depth"; },
       "uw.json: model.plots[2].exclude.e_r1: unknown channel with an outlier_column 'depth'"},
      {[](auto& m) { m["plots"][2]["exclude"]["e_x"] = "range1"; },
       "uw.json: model.plots[2].exclude.e_x: unknown series 'e_x'"},
      {[](auto& m) { m["plots"][2]["instants"] = false; },
       "uw.json: model.plots[2].exclude: applies to instants: set \"instants\": true"},
      {[](auto& m) { m["derived"]["e_d"]["expression"] = "dept - z_true"; },
       "uw.json: model.derived.e_d.expression: unknown symbol 'dept' at position 1: \"dept - "
       "z_true\" (did you mean 'depth'?)"},
      {[](auto& m) { m["version"] = 1; },
       "uw.json: model.expressions: a version-2 key: set \"version\": 2"},
  };
  for (const auto& c : cases) {
    nlohmann::json j = underwater_json();
    j["parameters"]["scheme"]["value"] = 1.0;  // SC: the stacked R is checked
    c.edit(j["model"]);
    const std::string got = load_error(j);
    EXPECT_EQ(got.substr(0, c.want.size()), c.want) << got;
  }
}

// The UKF has no stacked update: a run in SC says so (exit 2); AS and SI run.
TEST(ModelGroups, TheUkfRefusesTheStackedScheme) {
  auto m = testing::load_model_file(kFile);
  ASSERT_TRUE(m);
  ParamValues v = values(*m, 2, "SC");
  v["filter"] = choice(*m, "filter", "ukf");
  auto d = m->simulate(v);
  ASSERT_TRUE(d.ok());
  auto r = m->run(*d, v);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("model.groups.ranges: the stacked scheme runs in the kf or the ekf"),
            std::string::npos)
      << r.error();
  for (const char* scheme : {"AS", "SI"}) {
    ParamValues w = values(*m, 2, scheme);
    w["filter"] = choice(*m, "filter", "ukf");
    auto ok = m->run(*d, w);
    EXPECT_TRUE(ok.ok()) << scheme << ": " << ok.error();
  }
}

// An input's age: the time since its last sample, at t[k−1] in the prediction. x⁺ = x + age
// with u sampled at rows 0 and 4 of t = 0..6: the ages 0, 1, 2, 3, 0, 1 sum to x = 0, 0, 1, 3,
// 6, 6, 7 (the channel samples only the last row).
TEST(ModelGroups, AnInputsAgeIsTheTimeSinceItsLastSample) {
  const auto j = nlohmann::json::parse(R"J({
    "format": "kfw-preset", "version": 2, "scenario": "model", "title": "age",
    "parameters": {"q": {"value": 0.01, "min": 0, "max": 1}},
    "model": {"version": 2, "states": ["x"], "inputs": [{"name": "u", "age": "ua"}],
              "x0": ["0"], "P0": [["1"]], "process": {"f": ["x + ua"], "Q": [["q"]]},
              "measurements": {"pos": {"roles": ["z"], "H": [["1"]], "R": [["1"]]}},
              "filter": "ekf"}})J");
  auto s = make_model_scenario(j, "age.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const double nan = std::nan("");
  Dataset d;
  d.names = {"t", "u", "z"};
  d.columns = {
      {0, 1, 2, 3, 4, 5, 6}, {5, nan, nan, nan, 5, nan, nan}, {nan, nan, nan, nan, nan, nan, 7}};
  auto r = (*s)->run(d, (*s)->params().defaults());
  ASSERT_TRUE(r.ok()) << r.error();
  const Dataset out = (*r)->table();
  const std::vector<double> want = {0, 0, 1, 3, 6, 6};
  for (std::size_t k = 0; k < want.size(); ++k)
    EXPECT_DOUBLE_EQ(out.col("x.x")[k], want[k]) << "row " << k;
}

}  // namespace
}  // namespace model_groups_test
}  // namespace kfw
