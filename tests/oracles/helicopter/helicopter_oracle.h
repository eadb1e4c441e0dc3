// Test-only: what the retired built-in `helicopter` scenario did around the oracle — the seed
// preset's parameters (presets/helicopter.json, the built-in table's keys) as SimParams and
// FilterParams, its steady-state gains (closed form and DARE), and its run with the truth, the
// NEES and the shared metrics — moved from engine/scenarios/helicopter/helicopter_scenario.cpp
// (issue 30) so the model files are still compared with the filter and simulator they replaced.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/metrics.h"
#include "core/param_spec.h"
#include "core/statistics.h"
#include "filter/consistency.h"
#include "oracles/helicopter/helicopter_model.h"
#include "oracles/helicopter/helicopter_sim.h"
#include "oracles/helicopter/indirect_kf.h"

namespace kfw::helicopter {

inline SimParams sim_params(const ParamValues& v) {
  SimParams s;
  s.seed = static_cast<std::uint64_t>(param(v, "sim.seed"));
  s.duration_s = param(v, "sim.duration");
  s.Ts_s = param(v, "sim.Ts");
  s.amplitude_deg = param(v, "sim.amplitude");
  s.sigma_gyro = param(v, "sim.sigma_gyro");
  s.sigma_angle = param(v, "sim.sigma_angle");
  s.bias0 = param(v, "sim.bias0");
  s.bias_walk = param(v, "sim.bias_walk");
  s.angle_dropout = param(v, "sim.angle_dropout");
  s.P0_theta = param(v, "P0_theta");
  s.P0_bias = param(v, "P0_bias");
  return s;
}

inline FilterParams filter_params(const ParamValues& v) {
  FilterParams f;
  f.N_omega = param(v, "Q");
  f.N_theta = param(v, "R");
  f.m = static_cast<int>(param(v, "m"));
  f.gamma = param(v, "gamma");
  f.P0_theta = param(v, "P0_theta");
  f.P0_bias = param(v, "P0_bias");
  return f;
}

// The built-in's gain(): β, the closed forms k1(β) and p11⁻/N_θ (eq. 11), and the DARE of the
// m-step model (k1, k2, p11⁻/N_θ) at the sample period Ts.
inline Expected<Metrics> gain_at(const ParamValues& v, int m, double Ts) {
  const double Nw = param(v, "Q"), Nt = param(v, "R"), gamma = param(v, "gamma");
  Metrics g;
  g["beta"] = beta(m, Ts, Nw, Nt);
  g["k1"] = k1_closed_form(g["beta"]);
  g["p11_over_R"] = p11_over_R(g["beta"]);
  auto ss = steady_gain_dare(m, Ts, gamma, Nw, Nt);
  if (!ss) return ss.err();
  g["k1_dare"] = ss->k1;
  g["k2_dare"] = ss->k2;
  g["p11_over_R_dare"] = ss->p11_pred / Nt;
  return g;
}

// NEES of θ (truth holds θ only), or of [θ, b] with the simulator's bias truth. With γ > 0 the
// bias has no process noise: P22 decays as (1 − γ)^2k and P turns singular in double precision,
// where [θ, b]'s NEES is undefined; the run then reports θ's (1 dof).
inline void add_nees(HelicopterResult& r) {
  std::vector<double> nees(r.steps(), kNoSample);
  const std::vector<double>* bt = r.bias_truth.empty() ? nullptr : &r.bias_truth;
  bool joint = bt != nullptr;
  for (std::size_t k = 0; k < r.steps(); ++k) {
    const double e = r.theta[k] - r.truth[k];
    if (!std::isfinite(e)) continue;
    nees[k] = e * e / r.P11[k];
    if (!joint || !std::isfinite((*bt)[k])) continue;
    // e^T P^{-1} e with the 2×2 inverse written out.
    const double eb = r.bias[k] - (*bt)[k];
    const double a = r.P11[k], b = r.P12[k], c = r.P22[k], det = a * c - b * b;
    const double q = (c * e * e - 2.0 * b * e * eb + a * eb * eb) / det;
    if (det > 1e-12 * a * c && std::isfinite(q)) {
      nees[k] = q;
      continue;
    }
    joint = false;
    for (std::size_t j = 0; j <= k; ++j) {
      const double ej = r.theta[j] - r.truth[j];
      nees[j] = std::isfinite(ej) ? ej * ej / r.P11[j] : kNoSample;
    }
  }
  r.nees_dof = joint ? 2.0 : 1.0;
  r.nees = std::move(nees);
}

// rmse.<state> and rmse (θ, the primary state) as finalize_run gave them the built-in's states.
inline void add_rmse(HelicopterResult& r) {
  for (const auto& st : r.states()) {
    const std::string key = "rmse." + st.key;
    if (!st.truth || count_finite(*st.truth) == 0) {
      r.undefined.emplace(key, "no truth for '" + st.key + "' in the data");
    } else {
      r.metrics[key] = rmse_finite(*st.estimate, *st.truth);
    }
  }
  if (r.metrics.count("rmse.theta")) r.metrics["rmse"] = r.metrics.at("rmse.theta");
}

// The built-in's run: the indirect KF over t, gyro, angle (the columns must exist), truth and
// bias truth when the data have them, the NEES and the shared metrics (non-finite ones dropped).
inline HelicopterResult run_with_metrics(const Dataset& d, const ParamValues& v) {
  HelicopterResult r = run_indirect_kf(d.col("t"), d.col("gyro"), d.col("angle"), filter_params(v));
  r.truth = d.has("truth") ? d.col("truth") : std::vector<double>(d.rows(), kNoSample);
  if (d.has("bias_truth")) r.bias_truth = d.col("bias_truth");
  add_nees(r);
  add_rmse(r);
  add_consistency_metrics(r.channels(), r.nees_series(), r.metrics, r.undefined);
  for (auto it = r.metrics.begin(); it != r.metrics.end();) {
    it = std::isfinite(it->second) ? std::next(it) : r.metrics.erase(it);
  }
  return r;
}

}  // namespace kfw::helicopter
