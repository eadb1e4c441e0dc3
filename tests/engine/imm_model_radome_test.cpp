// Issue 28: seed 001's radome as a model file (presets/radome.json) equals the built-in
// scenario (since issue 30 the oracle in tests/oracles/radome/, its simulator, IMM and metric
// code): its world simulates the built-in's data to 1e-12, and on the same data its IMM gives
// the built-in's combined position and slope estimates to 1e-9 (../shared/STAGE.md's rule), in
// the axis and full structures, without and with renewal, under every reading and start.
//
// Where the run amplifies rounding — with renewal, and without it when the truth leaves the grid
// — the radome IMM is chaotic: the built-in against itself, its ranges changed by one part in
// 10¹³, drifts from 1e-13 to several σ by 60 s. There 1e-9 holds over the rows where the
// built-in is reproducible (expect_equal_runs), and beyond them the outcomes are the same over
// seeds (RenewalOutcomesAgreeOverSeeds).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/model_files.h"
#include "core/scenario.h"
#include "document/preset.h"
#include "experiment/monte_carlo.h"
#include "model/model_result.h"
#include "oracles/radome/radome_imm.h"
#include "oracles/radome/radome_metrics.h"
#include "oracles/radome/radome_params.h"
#include "oracles/radome/radome_sim.h"

namespace kfw {
namespace {

const std::string kRadomeFile = KFW_SOURCE_DIR "/presets/radome.json";

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) {
    if (std::isfinite(x)) m = std::max(m, std::fabs(x));
  }
  return m;
}

// |a − b| ≤ tol (|b| + scale) at every row where b is finite; a must be finite there too.
void expect_close(const std::vector<double>& a, const std::vector<double>& b,
                  const std::vector<double>& scale, double tol, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  int bad = 0;
  for (std::size_t k = 0; k < b.size() && bad < 3; ++k) {
    if (!std::isfinite(b[k])) continue;
    const double bound = tol * (std::fabs(b[k]) + scale[k]);
    if (!(std::fabs(a[k] - b[k]) <= bound)) {
      ADD_FAILURE() << what << " at row " << k << ": " << a[k] << " vs " << b[k] << " (bound "
                    << bound << ")";
      ++bad;
    }
  }
}

std::vector<double> constant(std::size_t n, double v) {
  return std::vector<double>(n, v);
}

TEST(ImmModelRadome, WorldSimulatesTheBuiltInsData) {
  auto s = testing::load_model_file(kRadomeFile);
  ASSERT_TRUE(s);
  for (double amplitude : {0.05, 0.08}) {
    for (int seed = 1; seed <= 5; ++seed) {
      ParamValues v = s->params().defaults();
      v["sim.seed"] = seed;
      v["sim.amplitude"] = amplitude;
      auto mine = s->simulate(v);
      ASSERT_TRUE(mine.ok()) << mine.error();
      auto theirs = radome::simulate(radome::sim_params(v));
      ASSERT_TRUE(theirs.ok()) << theirs.error();
      ASSERT_EQ(mine->rows(), theirs->rows());
      for (const char* col :
           {"t", "range_m", "psi_rad", "theta_rad", "psi_a_rad", "theta_a_rad", "ax_mps2", "x_m",
            "y_m", "z_m", "psi_los_rad", "theta_los_rad", "R_psi_true", "R_theta_true"}) {
        ASSERT_TRUE(mine->has(col)) << col;
        const auto& b = theirs->col(col);
        expect_close(mine->col(col), b, constant(b.size(), max_abs(b)), 1e-12,
                     std::string(col) + " seed " + std::to_string(seed));
      }
    }
  }
}

Expected<radome::RadomeResult> run_builtin(const Dataset& d, const std::vector<double>& range,
                                           const ParamValues& v) {
  radome::Inputs in;
  in.t = &d.col("t");
  in.range = &range;
  in.psi = &d.col("psi_rad");
  in.theta = &d.col("theta_rad");
  in.psi_a = &d.col("psi_a_rad");
  in.theta_a = &d.col("theta_a_rad");
  return radome::run_radome_imm(in, radome::filter_params(v));
}

// Per row, the largest normalised difference so far between `a` and the built-in `b`: position
// |Δ| / (|b| + σ_b), slope and grid centre |Δ| / span (STAGE.md's form), from row 1 (the
// built-in records row 0 from the raw angles, while its modes start from the centre-corrected
// ones, as the model file's do).
struct Series {
  const std::vector<double>* pos[3];
  const std::vector<double>* slope[2];
  const std::vector<double>* centre[2];
};
std::vector<double> drift(const Series& a, const radome::RadomeResult& b, double span) {
  const Series rb{{&b.x_est, &b.y_est, &b.z_est},
                  {&b.slope_psi, &b.slope_theta},
                  {&b.center_psi, &b.center_theta}};
  std::vector<double> out(b.t.size(), 0.0);
  double worst = 0.0;
  const auto at = [&](double x, double y, double scale) {
    if (std::isfinite(y)) worst = std::max(worst, std::fabs(x - y) / (std::fabs(y) + scale));
  };
  for (std::size_t k = 1; k < b.t.size(); ++k) {
    for (Eigen::Index i = 0; i < 3; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      at((*a.pos[ui])[k], (*rb.pos[ui])[k], std::sqrt(b.P_pos[k](i, i)));
    }
    for (std::size_t i = 0; i < 2; ++i) {
      at((*a.slope[i])[k], (*rb.slope[i])[k], span);
      at((*a.centre[i])[k], (*rb.centre[i])[k], span);
    }
    out[k] = worst;
  }
  return out;
}

// The model file and the built-in on the built-in's data at `v`: position and slope estimates,
// the grid's centre and the MAP mode's innovation equal to 1e-9 over the rows where the built-in
// is reproducible to 1e-10 (its ranges changed by 1e-13, 1 nm in 10 km, move it less); at
// least `min_rows` of them.
void expect_equal_runs(const Scenario& s, ParamValues v, const std::string& what,
                       std::size_t min_rows = 0) {
  auto d = radome::simulate(radome::sim_params(v));
  ASSERT_TRUE(d.ok()) << d.error();
  auto run = s.run(*d, v);
  ASSERT_TRUE(run.ok()) << what << ": " << run.error();
  const auto* m = dynamic_cast<const model::ModelResult*>(run->get());
  ASSERT_TRUE(m && m->imm && m->imm->axes.size() == 2) << what;
  auto ref = run_builtin(*d, d->col("range_m"), v);
  ASSERT_TRUE(ref.ok()) << ref.error();
  std::vector<double> nudged = d->col("range_m");
  for (double& r : nudged)
    r *= 1.0 + 1e-13;
  auto self = run_builtin(*d, nudged, v);
  ASSERT_TRUE(self.ok()) << self.error();
  const double span = v.at("grid.max") - v.at("grid.min");
  const auto& ax = m->imm->axes;
  const std::vector<double> mine = drift({{&m->x[0], &m->x[1], &m->x[2]},
                                          {&ax[0].estimate, &ax[1].estimate},
                                          {&ax[0].centre, &ax[1].centre}},
                                         *ref, span);
  const std::vector<double> own = drift({{&self->x_est, &self->y_est, &self->z_est},
                                         {&self->slope_psi, &self->slope_theta},
                                         {&self->center_psi, &self->center_theta}},
                                        *ref, span);
  // The rows where the built-in is reproducible 10 times below the tolerance.
  std::size_t rows = 1;
  while (rows < own.size() && own[rows] <= 1e-10)
    ++rows;
  for (std::size_t k = 1; k < rows; ++k) {
    ASSERT_LE(mine[k], 1e-9) << what << " at row " << k;
  }
  std::cout << what << ": compared over " << rows << " of " << own.size() << " rows; at the end "
            << mine.back() << " apart (the built-in from itself " << own.back() << ")\n";
  // The MAP mode's innovation is the built-in's (its pseudo-measurement less the prediction),
  // against the column's largest magnitude.
  const auto& ch = m->chans.at(0);
  for (std::size_t i = 0; i < 3; ++i) {
    const std::vector<double> head(ref->innovation[i].begin(),
                                   ref->innovation[i].begin() + static_cast<std::ptrdiff_t>(rows));
    const double scale = max_abs(head);
    for (std::size_t k = 1; k < rows; ++k) {
      const double b = ref->innovation[i][k];
      if (!std::isfinite(b)) continue;
      ASSERT_LE(std::fabs(ch.y[i][k] - b), 1e-9 * (std::fabs(b) + scale))
          << what << ", innovation " << i << " at row " << k;
    }
  }
  if (min_rows > 0) {
    EXPECT_GE(rows, min_rows) << what;
  }
}

TEST(ImmModelRadome, EqualsTheBuiltInInBothStructures) {
  auto s = testing::load_model_file(kRadomeFile);
  ASSERT_TRUE(s);
  for (double structure : {0.0, 1.0}) {
    for (double amplitude : {0.05, 0.08}) {
      ParamValues v = s->params().defaults();
      v["imm.structure"] = structure;
      v["sim.amplitude"] = amplitude;
      v["sim.seed"] = 2;
      // The truth inside the grid: the whole run; outside (0.08 > 0.05): 15 s at least.
      expect_equal_runs(
          *s, v,
          "structure " + std::to_string(structure) + ", amplitude " + std::to_string(amplitude),
          amplitude < 0.06 ? 1201 : 300);
    }
  }
}

TEST(ImmModelRadome, EqualsTheBuiltInUnderRenewal) {
  auto s = testing::load_model_file(kRadomeFile);
  ASSERT_TRUE(s);
  for (double structure : {0.0, 1.0}) {
    for (double reading : {0.0, 1.0, 2.0, 3.0}) {
      ParamValues v = s->params().defaults();
      v["imm.structure"] = structure;
      v["sim.amplitude"] = 0.08;
      v["Kp"] = 0.45;  // the paper's; the rate reading applies it per second
      v["renewal.mode"] = reading;
      expect_equal_runs(
          *s, v, "structure " + std::to_string(structure) + ", reading " + std::to_string(reading),
          60);
    }
  }
  for (double start : {0.0, 7.5}) {  // renewal.start
    ParamValues v = s->params().defaults();
    v["Kp"] = 0.45;
    v["renewal.start"] = start;
    v["grid.n_psi"] = 5;
    v["grid.n_theta"] = 3;
    v["grid.min"] = -0.08;
    v["grid.max"] = 0.02;
    // At least the rows before renewal starts.
    expect_equal_runs(*s, v, "renewal.start " + std::to_string(start), start > 0.0 ? 150 : 20);
  }
}

TEST(ImmModelRadome, BlockFiltersEqualTheWholeStateFilter) {
  // The axis structure runs three 3-state Kalman filters per mode (imm_blocks.h); the UKF runs
  // one 9-state filter per mode with the cross-block terms dropped (α = 1, β = 0, κ = 0: the KF
  // on a linear model to rounding). Truth A, no renewal: the same estimates to 1e-9.
  auto s = testing::load_model_file(kRadomeFile);
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  v["sim.seed"] = 4;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto blocks = s->run(*d, v);
  ASSERT_TRUE(blocks.ok()) << blocks.error();
  v["filter"] = 2.0;  // ukf
  v["ukf.alpha"] = 1.0;
  v["ukf.beta"] = 0.0;
  v["ukf.kappa"] = 0.0;
  auto whole = s->run(*d, v);
  ASSERT_TRUE(whole.ok()) << whole.error();
  const auto& a = dynamic_cast<const model::ModelResult&>(**blocks);
  const auto& b = dynamic_cast<const model::ModelResult&>(**whole);
  ASSERT_EQ(b.filter, "ukf");
  for (std::size_t i = 0; i < a.n(); ++i) {
    std::vector<double> sigma(b.steps());
    for (std::size_t k = 0; k < b.steps(); ++k)
      sigma[k] = std::sqrt(b.P[b.diag[i]][k]);
    expect_close(a.x[i], b.x[i], sigma, 1e-9, "state " + b.state_keys[i]);
  }
  expect_close(a.imm->axes[0].estimate, b.imm->axes[0].estimate, constant(b.steps(), 0.1), 1e-9,
               "slope");
}

TEST(ImmModelRadome, DerivedSeriesReadTheGridEstimates) {
  // In a derived series a grid axis's parameter is its IMM estimate: R_psi − R_psi_true is the
  // slope error whose RMS is rmse.R_psi.
  auto s = testing::load_model_file(kRadomeFile);
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  v["Kp"] = 0.45;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto run = s->run(*d, v);
  ASSERT_TRUE(run.ok()) << run.error();
  const Metrics& m = run->get()->metrics;
  for (const char* axis : {"psi", "theta"}) {
    const std::string p = std::string("R_") + axis;
    ASSERT_TRUE(m.count("rmse." + p) && m.count("derived.slope_err_" + std::string(axis) + ".rms"));
    EXPECT_NEAR(m.at("derived.slope_err_" + std::string(axis) + ".rms"), m.at("rmse." + p),
                1e-12 * m.at("rmse." + p));
  }
  EXPECT_LT(m.at("derived.refraction_err.rms"), 0.5);  // degrees
}

TEST(ImmModelRadome, NamedMetricsAreTheBuiltInsMetrics) {
  // The file's `metrics` block declares the built-in's scenario metrics under their names (the
  // paper's window t ≥ 10 s included), and `metrics_from` starts the standard ones (rmse,
  // rmse.x/y/z, NIS and NEES) at 10 s as the built-in did. The built-in's side is its metric code
  // on the oracle's run (oracles/radome/radome_metrics.h). Truth A without renewal, where both
  // runs are reproducible: equal to 1e-9 relative.
  auto s = testing::load_model_file(kRadomeFile);
  ASSERT_TRUE(s);
  for (double structure : {0.0, 1.0}) {
    ParamValues v = s->params().defaults();
    v["imm.structure"] = structure;
    v["sim.seed"] = 3;
    auto d = radome::simulate(radome::sim_params(v));
    ASSERT_TRUE(d.ok()) << d.error();
    auto mine = s->run(*d, v);
    ASSERT_TRUE(mine.ok()) << mine.error();
    auto ref = radome::run_radome_with_metrics(*d, radome::filter_params(v));
    ASSERT_TRUE(ref.ok()) << ref.error();
    const Metrics& a = mine->get()->metrics;
    const Metrics& b = ref->metrics;
    std::size_t compared = 0;
    for (const auto& [key, value] : a) {
      // Per channel the built-in's NIS and whiteness are of its whole run and other channels.
      if (!b.count(key) || key.rfind("nis_mean.", 0) == 0 || key.rfind("whiteness", 0) == 0) {
        continue;
      }
      EXPECT_NEAR(value, b.at(key), 1e-9 * std::max(1.0, std::fabs(b.at(key))))
          << key << ", structure " << structure;
      ++compared;
    }
    // rmse, rmse.x/y/z, nis_mean, nis_in_bounds, nees_mean, nees_in_bounds, 2 refraction and
    // 18 per axis.
    EXPECT_GE(compared, 28u);
    // The built-in's nis_mean is its one 3-D channel's over t ≥ 10 s, divided by 3.
    EXPECT_NEAR(a.at("nis_mean.seeker"), 3 * b.at("nis_mean"), 3e-9 * b.at("nis_mean"));
  }
}

// Seed 001, Figs. 7–9, with the reading that carries the mode states with the shift (`mix`, the
// default) and renewal from 2 s: truth B outside the grid is tracked (slope RMSE ≤ 0.0112, the
// refraction error under 0.5° in at least 7 of 10 seeds, every grid edge within 0.1 of the
// estimate), and renewal does not spoil truth A inside the grid (under 0.5° in 9 of 10). The
// built-in's renewal test (RadomeRenewal.CarryingTheModeStates…, which ran this file since issue
// 28), under the metric names the file declares.
// Truth B was "9 of 10" before the simulators drew from the random-number specification
// (CHANGES.md, issue 27): seeds 1–10 went from 10 to 7 (worst 0.478° → 0.542°, the three misses
// 0.52–0.54°) while over seeds 1–40 the share stayed (33 → 32 of 40; truth A 37 → 39 of 40).
TEST(ImmModelRadome, TheBuiltInsRenewalTestHoldsForTheFile) {
  auto s = testing::load_model_file(kRadomeFile);
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  ASSERT_EQ(v.at("renewal.mode"), 3.0);
  ASSERT_EQ(v.at("renewal.start"), 2.0);
  v["Kp"] = 0.45;
  std::vector<long long> seeds;
  for (long long seed = 1; seed <= 10; ++seed)
    seeds.push_back(seed);
  for (double amplitude : {0.08, 0.05}) {
    v["sim.amplitude"] = amplitude;
    auto part = run_monte_carlo(*s, v, seeds);
    ASSERT_TRUE(part.ok()) << part.error();
    int under = 0;
    double rmse_psi = 0.0, rmse_theta = 0.0;
    for (const auto& run : part->runs) {
      const Metrics& m = run.metrics;
      under += m.at("refraction_err_max_deg") < 0.5 ? 1 : 0;
      rmse_psi += m.at("slope_rmse_psi") / 10.0;
      rmse_theta += m.at("slope_rmse_theta") / 10.0;
      EXPECT_LE(m.at("grid_span_psi"), 0.1 + 1e-9);
      EXPECT_LE(m.at("grid_span_theta"), 0.1 + 1e-9);
    }
    std::cout << "amplitude " << amplitude << ": " << under << " of 10 under 0.5°, slope RMSE "
              << rmse_psi << " / " << rmse_theta << "\n";
    EXPECT_GE(under, amplitude == 0.08 ? 7 : 9) << "amplitude " << amplitude;
    if (amplitude == 0.08) {
      EXPECT_LE(rmse_psi, 0.0112);
      EXPECT_LE(rmse_theta, 0.0112);
    }
  }
  // Without renewal, truth B leaves the grid and the refraction error exceeds 0.5°.
  v["Kp"] = 0.0;
  v["sim.amplitude"] = 0.08;
  v["sim.seed"] = 1;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto run = s->run(*d, v);
  ASSERT_TRUE(run.ok()) << run.error();
  EXPECT_GT(run->get()->metrics.at("refraction_err_max_deg"), 0.5);
}

// RMSE over t ≥ 10 s (the built-in's metrics window) of `est` against `truth`.
double rmse_after_10s(const std::vector<double>& t, const std::vector<double>& est,
                      const std::vector<double>& truth) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < 10.0 || !std::isfinite(est[k]) || !std::isfinite(truth[k])) continue;
    sum += (est[k] - truth[k]) * (est[k] - truth[k]);
    ++n;
  }
  return std::sqrt(sum / n);
}

TEST(ImmModelRadome, RenewalOutcomesAgreeOverSeeds) {
  // The paper's renewal (Kp 0.45, truth B) over seeds 1..10, paired on the same data: the model
  // file's slope and position RMSE differ from the built-in's by no more than chance (3 standard
  // errors of the paired differences), and both meet the paper's slope accuracy.
  auto s = testing::load_model_file(kRadomeFile);
  ASSERT_TRUE(s);
  const int seeds = 10;
  std::vector<std::vector<double>> diff(3);
  std::vector<double> mine_mean(3, 0.0), ref_mean(3, 0.0);
  for (int seed = 1; seed <= seeds; ++seed) {
    ParamValues v = s->params().defaults();
    v["sim.seed"] = seed;
    v["sim.amplitude"] = 0.08;
    v["Kp"] = 0.45;
    auto d = radome::simulate(radome::sim_params(v));
    ASSERT_TRUE(d.ok()) << d.error();
    auto run = s->run(*d, v);
    ASSERT_TRUE(run.ok()) << run.error();
    const auto* m = dynamic_cast<const model::ModelResult*>(run->get());
    ASSERT_TRUE(m && m->imm);
    auto ref = run_builtin(*d, d->col("range_m"), v);
    ASSERT_TRUE(ref.ok()) << ref.error();
    const auto& t = d->col("t");
    std::vector<double> pos_m(t.size()), pos_r(t.size()), truth0(t.size(), 0.0);
    for (std::size_t k = 0; k < t.size(); ++k) {
      const double ex = m->x[0][k] - d->col("x_m")[k], ey = m->x[1][k] - d->col("y_m")[k],
                   ez = m->x[2][k] - d->col("z_m")[k];
      const double rx = ref->x_est[k] - d->col("x_m")[k], ry = ref->y_est[k] - d->col("y_m")[k],
                   rz = ref->z_est[k] - d->col("z_m")[k];
      pos_m[k] = std::sqrt(ex * ex + ey * ey + ez * ez);
      pos_r[k] = std::sqrt(rx * rx + ry * ry + rz * rz);
    }
    const double mine[3] = {rmse_after_10s(t, m->imm->axes[0].estimate, d->col("R_psi_true")),
                            rmse_after_10s(t, m->imm->axes[1].estimate, d->col("R_theta_true")),
                            rmse_after_10s(t, pos_m, truth0)};
    const double theirs[3] = {rmse_after_10s(t, ref->slope_psi, d->col("R_psi_true")),
                              rmse_after_10s(t, ref->slope_theta, d->col("R_theta_true")),
                              rmse_after_10s(t, pos_r, truth0)};
    for (std::size_t i = 0; i < 3; ++i) {
      diff[i].push_back(mine[i] - theirs[i]);
      mine_mean[i] += mine[i] / seeds;
      ref_mean[i] += theirs[i] / seeds;
    }
  }
  const char* names[3] = {"slope RMSE psi", "slope RMSE theta", "position RMSE (m)"};
  for (std::size_t i = 0; i < 3; ++i) {
    double mean = 0.0, var = 0.0;
    for (double x : diff[i])
      mean += x / seeds;
    for (double x : diff[i])
      var += (x - mean) * (x - mean) / (seeds - 1);
    const double se = std::sqrt(var / seeds);
    std::cout << names[i] << ": model file " << mine_mean[i] << ", built-in " << ref_mean[i]
              << ", paired difference " << mean << " ± " << se << "\n";
    EXPECT_LE(std::fabs(mean), 3.0 * se + 1e-12) << names[i];
  }
  EXPECT_LE(mine_mean[0], 0.0112);
  EXPECT_LE(mine_mean[1], 0.0112);
}

// Monte Carlo's x0 from the prior: the file's world simulates its own engagement and the filter
// starts at the first pseudo-measurement, so there is no prior to draw the truth from (the
// built-in radome refused it too).
TEST(ImmModelRadome, X0FromThePriorIsRefused) {
  std::ifstream in(kRadomeFile);
  auto j = nlohmann::ordered_json::parse(in);
  j["sim"] = {{"x0_from_prior", true}};
  auto p = parse_preset(j.dump(), "r.json");
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error(),
            "r.json: sim.x0_from_prior: the model's world simulates its own initial state and the "
            "filter starts from a channel's first sample, so it cannot draw its initial state "
            "from the filter's prior");
}

}  // namespace
}  // namespace kfw
