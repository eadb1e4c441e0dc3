#include "oracles/radome/radome_metrics.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <string>
#include <utility>

#include "core/statistics.h"
#include "filter/consistency.h"
#include "oracles/radome/radome_model.h"

namespace kfw::radome {

namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr double kMetricsFrom_s = 10.0;  // seed 001 metrics skip the first 10 s (convergence)

std::size_t first_index_from(const std::vector<double>& t, double from_s) {
  if (t.empty()) return 0;
  const double t0 = t.front() + from_s;
  return static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), t0 - 1e-9) - t.begin());
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b, std::size_t from) {
  double m = kNoSample;
  for (std::size_t k = from; k < a.size() && k < b.size(); ++k) {
    if (!std::isfinite(a[k]) || !std::isfinite(b[k])) continue;
    const double d = std::abs(a[k] - b[k]);
    if (!(m >= d)) m = d;
  }
  return m;
}

void add_truth(RadomeResult& r, const Dataset& d) {
  const std::size_t n = d.rows();
  auto col_or_nan = [&](const char* name) {
    return d.has(name) ? d.col(name) : std::vector<double>(n, kNoSample);
  };
  r.slope_psi_true = col_or_nan("R_psi_true");
  r.slope_theta_true = col_or_nan("R_theta_true");
  r.x_true = col_or_nan("x_m");
  r.y_true = col_or_nan("y_m");
  r.z_true = col_or_nan("z_m");
  const std::vector<double> psi_los = col_or_nan("psi_los_rad");
  const std::vector<double> theta_los = col_or_nan("theta_los_rad");
  const auto& zp = d.col("psi_rad");
  const auto& zt = d.col("theta_rad");
  const auto& pa = d.col("psi_a_rad");
  const auto& ta = d.col("theta_a_rad");
  r.psi_los_true_deg.assign(n, kNoSample);
  r.theta_los_true_deg.assign(n, kNoSample);
  r.alpha_true_deg.assign(n, kNoSample);
  r.alpha_meas_deg.assign(n, kNoSample);
  for (std::size_t k = 0; k < n; ++k) {
    r.psi_los_true_deg[k] = psi_los[k] * kRadToDeg;
    r.theta_los_true_deg[k] = theta_los[k] * kRadToDeg;
    // α from the truth slopes (seed 001, Sec. 2.1); NaN propagates where truth is absent.
    r.alpha_true_deg[k] = refraction_error(r.slope_psi_true[k], r.slope_theta_true[k], psi_los[k],
                                           theta_los[k], pa[k], ta[k]) *
                          kRadToDeg;
    if (!std::isfinite(r.slope_psi_true[k]) || !std::isfinite(psi_los[k])) {
      r.alpha_true_deg[k] = kNoSample;
    }
    // The realised boresight error: measured direction against the true LOS (noise included).
    const double c = std::cos(zt[k] - theta_los[k]) * std::cos(zp[k] - psi_los[k]);
    r.alpha_meas_deg[k] =
        std::isfinite(c) ? std::acos(std::clamp(c, -1.0, 1.0)) * kRadToDeg : kNoSample;
  }
}

// The grid envelope (Fig. 9: about ±0.07 with Kp = 0.45), how far the centre moved, and how far
// the grid reaches around the estimate (renewal: about its half-width).
void add_grid_metrics(RadomeResult& r) {
  Metrics& m = r.metrics;
  double lo_p = kNoSample, hi_p = kNoSample, lo_t = kNoSample, hi_t = kNoSample;
  double cmax_p = 0.0, cmax_t = 0.0, span_p = 0.0, span_t = 0.0;
  const double op_lo = r.offsets_psi.front(), op_hi = r.offsets_psi.back();
  const double ot_lo = r.offsets_theta.front(), ot_hi = r.offsets_theta.back();
  for (std::size_t k = 0; k < r.steps(); ++k) {
    if (std::isfinite(r.center_psi[k])) {
      const double a = r.center_psi[k] + op_lo, b = r.center_psi[k] + op_hi;
      const double c = r.center_theta[k] + ot_lo, e = r.center_theta[k] + ot_hi;
      if (!(lo_p <= a)) lo_p = a;
      if (!(hi_p >= b)) hi_p = b;
      if (!(lo_t <= c)) lo_t = c;
      if (!(hi_t >= e)) hi_t = e;
      cmax_p = std::max(cmax_p, std::abs(r.center_psi[k]));
    }
    if (std::isfinite(r.center_theta[k])) cmax_t = std::max(cmax_t, std::abs(r.center_theta[k]));
    if (std::isfinite(r.center_psi[k]) && std::isfinite(r.slope_psi[k])) {
      const double c = r.center_psi[k] - r.slope_psi[k];
      span_p = std::max({span_p, std::abs(c + op_lo), std::abs(c + op_hi)});
    }
    if (std::isfinite(r.center_theta[k]) && std::isfinite(r.slope_theta[k])) {
      const double c = r.center_theta[k] - r.slope_theta[k];
      span_t = std::max({span_t, std::abs(c + ot_lo), std::abs(c + ot_hi)});
    }
  }
  m["grid_center_psi_final"] = last_finite(r.center_psi);
  m["grid_center_theta_final"] = last_finite(r.center_theta);
  m["grid_span_psi"] = span_p;
  m["grid_span_theta"] = span_t;
  m["grid_center_psi_max_abs"] = cmax_p;
  m["grid_center_theta_max_abs"] = cmax_t;
  m["grid_psi_min_reached"] = lo_p;
  m["grid_psi_max_reached"] = hi_p;
  m["grid_theta_min_reached"] = lo_t;
  m["grid_theta_max_reached"] = hi_t;
}

// RMS distance of the 3-D position and its components, t ≥ 10 s.
void add_position_metrics(RadomeResult& r, const Dataset& d, std::size_t from) {
  Metrics& m = r.metrics;
  if (!d.has("x_m")) {
    for (const char* k : {"rmse", "rmse.x", "rmse.y", "rmse.z"})
      r.undefined.emplace(k, "no truth position (x_m, y_m, z_m) in the data");
    return;
  }
  double se = 0.0;
  std::size_t cnt = 0;
  for (std::size_t k = from; k < r.steps(); ++k) {
    const double ex = r.x_est[k] - r.x_true[k], ey = r.y_est[k] - r.y_true[k],
                 ez = r.z_est[k] - r.z_true[k];
    const double e2 = ex * ex + ey * ey + ez * ez;
    if (std::isfinite(e2)) {
      se += e2;
      ++cnt;
    }
  }
  m["rmse"] = cnt ? std::sqrt(se / static_cast<double>(cnt)) : kNoSample;
  m["rmse.x"] = rmse_finite(r.x_est, r.x_true, from);
  m["rmse.y"] = rmse_finite(r.y_est, r.y_true, from);
  m["rmse.z"] = rmse_finite(r.z_est, r.z_true, from);
}

// Why a radome metric has no value: the truth it compares against is missing, or the run ends
// before the 10 s that the error metrics skip (anything else: "no finite value", below).
void explain_undefined(RadomeResult& r, const Dataset& d, std::size_t from) {
  auto has = [&](std::initializer_list<const char*> cols) {
    for (const char* c : cols) {
      if (!d.has(c) || count_finite(d.col(c)) == 0) return false;
    }
    return true;
  };
  const bool short_run = from >= r.steps();
  const std::string short_why = "the run ends within the first 10 s, which the metrics skip";
  auto explain = [&](std::initializer_list<const char*> keys, bool truth, const std::string& why,
                     bool skips_start = true) {
    for (const char* k : keys) {
      auto it = r.metrics.find(k);
      if (it != r.metrics.end() && std::isfinite(it->second)) continue;
      if (!truth) {
        r.undefined.emplace(k, why);
      } else if (skips_start && short_run) {
        r.undefined.emplace(k, short_why);
      }
    }
  };
  const bool slopes = has({"R_psi_true", "R_theta_true"});
  const bool los = has({"psi_los_rad", "theta_los_rad"});
  explain({"slope_rmse_psi", "slope_rmse_theta", "slope_err_max_psi", "slope_err_max_theta"},
          slopes, "no true slope (R_psi_true, R_theta_true) in the data");
  explain({"refraction_err_max_deg", "refraction_err_rmse_deg"}, slopes && los,
          "no true slope and LOS (R_*_true, *_los_rad) in the data");
  explain({"los_est_err_max_psi_deg", "los_est_err_max_theta_deg"}, los,
          "no true LOS (psi_los_rad, theta_los_rad) in the data");
  explain({"los_err_max_psi_deg", "los_err_max_theta_deg"}, los,
          "no true LOS (psi_los_rad, theta_los_rad) in the data", false);
  explain({"rmse", "rmse.x", "rmse.y", "rmse.z"}, has({"x_m", "y_m", "z_m"}),
          "no truth position (x_m, y_m, z_m) in the data");
  explain({"nis_mean", "nis_in_bounds"}, true, "");
  // add_consistency_metrics would fill these from the whole run; they, too, skip the start.
  if (short_run) {
    for (const char* k : {"nees_mean", "nees_in_bounds"})
      r.undefined.emplace(k, short_why);
  }
}

void compute_metrics(RadomeResult& r, const Dataset& d) {
  Metrics& m = r.metrics;
  const std::size_t from = first_index_from(r.t, kMetricsFrom_s);
  m["slope_rmse_psi"] = rmse_finite(r.slope_psi, r.slope_psi_true, from);
  m["slope_rmse_theta"] = rmse_finite(r.slope_theta, r.slope_theta_true, from);
  m["slope_err_max_psi"] = max_abs_diff(r.slope_psi, r.slope_psi_true, from);
  m["slope_err_max_theta"] = max_abs_diff(r.slope_theta, r.slope_theta_true, from);
  m["refraction_err_max_deg"] = max_abs_diff(r.alpha_est_deg, r.alpha_true_deg, from);
  m["refraction_err_rmse_deg"] = rmse_finite(r.alpha_est_deg, r.alpha_true_deg, from);
  add_grid_metrics(r);
  // Measured-vs-true LOS difference (seed 001, Fig. 3: about ±2°).
  m["los_err_max_psi_deg"] = max_abs_diff(r.psi_meas_deg, r.psi_los_true_deg, 0);
  m["los_err_max_theta_deg"] = max_abs_diff(r.theta_meas_deg, r.theta_los_true_deg, 0);
  m["los_est_err_max_psi_deg"] = max_abs_diff(r.psi_los_est_deg, r.psi_los_true_deg, from);
  m["los_est_err_max_theta_deg"] = max_abs_diff(r.theta_los_est_deg, r.theta_los_true_deg, from);
  add_position_metrics(r, d, from);
  // NIS of the 3-D pseudo-measurement over t ≥ 10 s, divided by its 3 dof.
  m["nis_mean"] = mean_finite(r.nis, from) / 3.0;
  m["nis_in_bounds"] = fraction_inside(
      std::vector<double>(r.nis.begin() + static_cast<std::ptrdiff_t>(std::min(from, r.nis.size())),
                          r.nis.end()),
      3.0);
  // NEES of the combined position (truth covers x, y, z only: dof 3), over t ≥ 10 s like NIS.
  if (r.nees.size() > from) {
    const std::vector<double> tail(r.nees.begin() + static_cast<std::ptrdiff_t>(from),
                                   r.nees.end());
    if (count_finite(tail)) {
      m["nees_mean"] = mean_finite(tail) / r.nees_dof;
      m["nees_in_bounds"] = fraction_inside(tail, r.nees_dof);
    }
  }
  add_consistency_metrics(r.channels(), r.nees_series(), m, r.undefined);  // per channel
  m["modes"] = r.modes();
  m["updates"] = static_cast<double>(r.updates);
  m["steps"] = static_cast<double>(r.steps());
  m["Ts"] = d.median_dt();
  explain_undefined(r, d, from);
}

}  // namespace

void add_radome_metrics(RadomeResult& r, const Dataset& d) {
  add_truth(r, d);
  r.compute_nees();
  compute_metrics(r, d);
  // finalize_run's last step: only finite values are metrics.
  for (auto it = r.metrics.begin(); it != r.metrics.end();) {
    if (std::isfinite(it->second)) {
      ++it;
      continue;
    }
    r.undefined.emplace(it->first, "no finite value in this run");
    it = r.metrics.erase(it);
  }
  for (const auto& [key, why] : r.undefined)
    r.metrics.erase(key);
}

Expected<RadomeResult> run_radome_with_metrics(const Dataset& d, const FilterParams& p,
                                               const RunControl& control) {
  Inputs in;
  in.t = &d.col("t");
  in.range = &d.col("range_m");
  in.psi = &d.col("psi_rad");
  in.theta = &d.col("theta_rad");
  in.psi_a = &d.col("psi_a_rad");
  in.theta_a = &d.col("theta_a_rad");
  const char* u_names[3] = {"ax_mps2", "ay_mps2", "az_mps2"};
  for (std::size_t ax = 0; ax < 3; ++ax) {
    if (d.has(u_names[ax])) in.U[ax] = &d.col(u_names[ax]);
  }
  auto r = run_radome_imm(in, p, control);
  if (!r) return Error{d.source + ": " + r.error()};
  add_radome_metrics(*r, d);
  return r;
}

}  // namespace kfw::radome
