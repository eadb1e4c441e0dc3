// The `radome` scenario (seed 001; docs/reproductions.md): parameter table, schema, simulator and
// runner.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

#include "core/scenario.h"
#include "core/statistics.h"
#include "filter/consistency.h"
#include "scenarios/radome/radome_imm.h"
#include "scenarios/radome/radome_model.h"
#include "scenarios/radome/radome_sim.h"

namespace kfw {

namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr double kMetricsFrom_s = 10.0;  // seed 001 metrics skip the first 10 s (convergence)

ParamTable make_table() {
  const std::string F = "Filter", G = "IMM grid", S = "Simulator";
  return ParamTable({
      {"Q", "Q, target manoeuvre noise density", "(m/s²)²/Hz", 1e-3, 1e6, 100.0, Scale::kLog, F,
       "Spectral density of w driving A_T through D = I/τ (Kim & Back 2017, eq. 1); same per "
       "axis."},
      {"tau", "τ, target manoeuvre time constant", "s", 0.05, 100.0, 0.5, Scale::kLog, F,
       "A = [[0, I, 0], [0, 0, I], [0, 0, −I/τ]] (Kim & Back 2017, eq. 1)."},
      {"R", "R, angle noise variance", "rad²", 1e-10, 1e-2, 1e-6, Scale::kLog, F,
       "Variance of ν_ψ and ν_θ (Kim & Back 2017, Sec. 3.1: 1e-6)."},
      {"R_range", "range noise variance", "m²", 1e-8, 1e4, 1.0, Scale::kLog, F,
       "Variance of ν_R in the filter. The data have 1e-6 (Kim & Back 2017), but the linearised "
       "pseudo-measurement is off by r σ_ψ²/2 ≈ 5 mm along the LOS at 10 km, so the filter "
       "assumes 1 m² (matters for the full structure)."},
      {"P0_pos", "P0 position variance", "m²", 1e-2, 1e8, 1e4, Scale::kLog, F,
       "Initial variance of x, y, z (each mode starts at the first pseudo-measurement)."},
      {"P0_vel", "P0 velocity variance", "(m/s)²", 1e-2, 1e8, 1e6, Scale::kLog, F,
       "Initial variance of the relative velocity (starts at 0)."},
      {"P0_acc", "P0 acceleration variance", "(m/s²)²", 1e-2, 1e6, 100.0, Scale::kLog, F,
       "Initial variance of the target acceleration (starts at 0)."},
      {"imm.structure",
       "mode filter structure",
       "",
       0,
       1,
       0,
       Scale::kChoice,
       F,
       "axis: three 3-state filters per mode with the diagonal of the converted covariance "
       "(fast); full: one 9-state filter per mode with the full 3×3 converted covariance.",
       0,
       {"axis", "full"}},
      {"Kp", "Kp, mode-parameter renewal gain", "", 0.0, 1.0, 0.0, Scale::kLinear, G,
       "ΔR̄_k = Kp (R̂_{k−1} − mean R̄_{k−1}) moves the grid (Kim & Back 2017, eq. 4); 0 = plain IMM.",
       3},
      {"renewal.mode",
       "renewal: what μ and Kp mean",
       "",
       0,
       3,
       3,
       Scale::kChoice,
       G,
       "index: eq. 4 every sample, μ stays with the grid index; slope: μ shared between the moved "
       "grid's neighbours of its slope; rate: Kp per second (ΔR̄ = Kp·Ts·(R̂ − R̄)), μ by index. "
       "mix: the shift as a mode transition, μ and the mode states carried to the moved grid. "
       "README: the reading of eq. 4 (mix, the default, reproduces Figs. 7–9).",
       0,
       {"index", "slope", "rate", "mix"}},
      {"renewal.start", "renewal starts after", "s", 0.0, 600.0, 2.0, Scale::kLinear, G,
       "No renewal for this long after the first measurement: the IMM's start-up transient "
       "(large P0) would steer the grid. The paper does not say when renewal starts.",
       1},
      // The initial grid brackets zero: min in [−0.5, 0], max in [0, 0.5]. A radome's slope
      // changes sign across the look-angle cone (the truth, eq. 5, is a sinusoid about 0) and
      // the renewal (Kp) moves the grid from there; ranges that crossed (either end over the
      // other's preset value) let a value inside its declared range reverse the grid.
      {"grid.min", "grid minimum slope", "", -0.5, 0.0, -0.05, Scale::kLinear, G,
       "Smallest slope of the initial grid, both axes (Kim & Back 2017, eq. 6: −0.05); ≤ 0: "
       "the grid brackets zero, where a radome's slope changes sign.",
       3},
      {"grid.max", "grid maximum slope", "", 0.0, 0.5, 0.05, Scale::kLinear, G,
       "Largest slope of the initial grid, both axes (Kim & Back 2017, eq. 6: +0.05); ≥ 0: "
       "the grid brackets zero, where a radome's slope changes sign.",
       3},
      {"grid.n_psi", "n_ψ, azimuth slopes", "", 1, 15, 7, Scale::kInteger, G,
       "Number of R̄_ψ values (Kim & Back 2017: 7)."},
      {"grid.n_theta", "n_θ, elevation slopes", "", 1, 15, 7, Scale::kInteger, G,
       "Number of R̄_θ values (Kim & Back 2017: 7); n_ψ × n_θ modes."},
      {"markov.stay", "Markov stay probability", "", 0.001, 1.0, 0.99, Scale::kLinear, G,
       "p^{jj}; the rest spread equally over the other modes, so mixing is O(r).", 4},
      {"sim.seed", "seed", "", 0, 1e6, 1, Scale::kInteger, S, "Random seed of the simulator."},
      {"sim.amplitude", "truth slope amplitude", "", 0.0, 0.3, 0.05, Scale::kLinear, S,
       "R_ψ = A sin(0.03πt − 0.25π), R_θ = A sin(0.03πt): 0.05 eq. 5 (inside the grid), 0.08 "
       "eq. 7 (outside).",
       3},
      {"sim.duration", "duration", "s", 1, 600, 60, Scale::kLinear, S, "Kim & Back 2017: 60 s.", 0},
      {"sim.Ts", "sample period", "s", 0.005, 1.0, 0.05, Scale::kLinear, S,
       "Seeker sample period (not in the paper; 20 Hz).", 3},
      {"sim.range0", "initial range", "m", 1000, 50000, 10000, Scale::kLinear, S,
       "Kim & Back 2017: 10 km.", 0},
      {"sim.az0", "initial LOS azimuth", "deg", -60, 60, 0, Scale::kLinear, S,
       "The target flies so the LOS direction (without its weave) stays at (az0, el0).", 1},
      {"sim.el0", "initial LOS elevation", "deg", -60, 60, 0, Scale::kLinear, S, "", 1},
      {"sim.weave", "aircraft attitude weave", "deg", 0, 60, 30, Scale::kLinear, S,
       "Body (boresight) attitude cones about the flight path, ψ_a = w sin(2πt/P), θ_a = w "
       "cos(2πt/P): look angles reach ±w, so R (λ − λ_a) reaches ±1.5° (0.05) / ±2.4° (0.08).",
       1},
      {"sim.weave_period", "weave period P", "s", 0.5, 60, 4, Scale::kLinear, S, "", 1},
      {"sim.target_g", "target manoeuvre", "g", 0, 9, 1, Scale::kLinear, S,
       "Target weave a_T = g_T [0, cos(2πt/20 s), cos(2πt/14 s)] (Kim & Back 2017: 1 g in y and "
       "z).",
       2},
      {"sim.R", "angle noise variance", "rad²", 0, 1e-2, 1e-6, Scale::kLinear, S,
       "ν_ψ, ν_θ ~ N(0, 1e-6) (Kim & Back 2017).", 8},
      {"sim.R_range", "range noise variance", "m²", 0, 1e4, 1e-6, Scale::kLinear, S,
       "ν_R ~ N(0, 1e-6) (Kim & Back 2017).", 8},
  });
}

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

// The radome metrics beyond the shared vocabulary. Error metrics skip the first 10 s
// (kMetricsFrom_s), as seed 001 does.
std::vector<MetricSpec> make_metric_specs() {
  using G = MetricGroup;
  using D = Direction;
  std::vector<MetricSpec> v = {
      // The shared `rmse`, made specific: the 3-D position is a compound, not one state.
      {"rmse", "RMSE of the 3-D position", "m",
       "RMS distance between the estimated and true relative position, t ≥ 10 s", G::kAccuracy,
       D::kLower},
      {"refraction_err_max_deg", "largest refraction-angle error", "deg",
       "largest |α̂ − α| of the boresight refraction angle, t ≥ 10 s (Kim & Back 2017: within 0.5°)",
       G::kAccuracy, D::kLower},
      {"refraction_err_rmse_deg", "refraction-angle RMSE", "deg",
       "RMS of α̂ − α, the boresight refraction angle, t ≥ 10 s", G::kAccuracy, D::kLower},
      {"modes", "modes", "", "number of mode-matched filters (n_ψ × n_θ)", G::kScenario, D::kNone},
      {"updates", "updates", "", "number of measurement updates", G::kScenario, D::kNone},
      {"steps", "steps", "", "number of samples in the run", G::kScenario, D::kNone},
      {"Ts", "sample period", "s", "median sample period of the data", G::kScenario, D::kNone},
  };
  for (const auto& [ax, sym] : {std::pair{"psi", "ψ"}, std::pair{"theta", "θ"}}) {
    const std::string a = ax, y = sym;
    v.push_back({"slope_rmse_" + a, "slope RMSE " + y, "",
                 "RMS of the estimated minus the true radome slope R_" + y + ", t ≥ 10 s",
                 G::kAccuracy, D::kLower});
    v.push_back({"slope_err_max_" + a, "largest slope error " + y, "",
                 "largest |R̂_" + y + " − R_" + y + "|, t ≥ 10 s", G::kAccuracy, D::kLower});
    v.push_back(
        {"grid_center_" + a + "_final", "final grid centre " + y, "",
         "centre of the slope grid along " + y + " at the end of the run (moves when Kp > 0)",
         G::kScenario, D::kLower});
    v.push_back({"grid_center_" + a + "_max_abs", "largest |grid centre| " + y, "",
                 "furthest the grid centre moved from 0 along " + y + " (renewal, eq. 4)",
                 G::kScenario, D::kLower});
    v.push_back({"grid_span_" + a, "grid span around the estimate " + y, "",
                 "furthest a grid edge along " + y +
                     " was from the slope estimate R̂ (Kim & Back 2017, Figs. 7–9: about 0.07 with "
                     "Kp = 0.45)",
                 G::kScenario, D::kNone});
    v.push_back({"grid_" + a + "_min_reached", "lowest grid slope " + y, "",
                 "smallest slope any grid edge reached along " + y + " (Kim & Back 2017, Fig. 9)",
                 G::kScenario, D::kLower});
    v.push_back({"grid_" + a + "_max_reached", "highest grid slope " + y, "",
                 "largest slope any grid edge reached along " + y + " (Kim & Back 2017, Fig. 9)",
                 G::kScenario, D::kLower});
    v.push_back({"los_err_max_" + a + "_deg", "largest measured LOS error " + y, "deg",
                 "largest |measured − true| LOS angle " + y +
                     ", whole run: what the radome does to the seeker (Kim & Back 2017, Fig. 3)",
                 G::kScenario, D::kLower});
    v.push_back({"los_est_err_max_" + a + "_deg", "largest estimated LOS error " + y, "deg",
                 "largest |estimated − true| LOS angle " + y + ", t ≥ 10 s", G::kAccuracy,
                 D::kLower});
  }
  return v;
}

class RadomeScenario final : public Scenario {
 public:
  std::string name() const override { return "radome"; }
  std::vector<MetricSpec> metric_specs() const override {
    static const std::vector<MetricSpec> specs = make_metric_specs();
    return specs;
  }
  std::string title() const override {
    return "Radome slope: IMM over a slope grid with mode-parameter renewal (Kim & Back 2017)";
  }
  const ParamTable& params() const override {
    static const ParamTable table = make_table();
    return table;
  }
  std::vector<ColumnSpec> columns() const override {
    return {{"t", "s", "time", true},
            {"range_m", "m", "measured range z_R", true},
            {"psi_rad", "rad", "measured (refracted) LOS azimuth z_ψ", true},
            {"theta_rad", "rad", "measured (refracted) LOS elevation z_θ", true},
            {"psi_a_rad", "rad", "aircraft attitude ψ_a", true},
            {"theta_a_rad", "rad", "aircraft attitude θ_a", true},
            {"ax_mps2", "m/s²", "aircraft acceleration U_x (0 when absent)", false},
            {"ay_mps2", "m/s²", "aircraft acceleration U_y", false},
            {"az_mps2", "m/s²", "aircraft acceleration U_z", false},
            {"psi_los_rad", "rad", "true LOS azimuth", false},
            {"theta_los_rad", "rad", "true LOS elevation", false},
            {"R_psi_true", "", "true azimuth radome slope", false},
            {"R_theta_true", "", "true elevation radome slope", false},
            {"x_m", "m", "true relative x", false},
            {"y_m", "m", "true relative y", false},
            {"z_m", "m", "true relative z", false}};
  }

  Expected<Dataset> simulate(const ParamValues& v) const override {
    if (auto st = params().check(v); !st) return st.err();
    radome::SimParams s;
    s.seed = static_cast<std::uint64_t>(param(v, "sim.seed"));
    s.amplitude = param(v, "sim.amplitude");
    s.duration_s = param(v, "sim.duration");
    s.Ts_s = param(v, "sim.Ts");
    s.range0_m = param(v, "sim.range0");
    s.az0_deg = param(v, "sim.az0");
    s.el0_deg = param(v, "sim.el0");
    s.weave_deg = param(v, "sim.weave");
    s.weave_period_s = param(v, "sim.weave_period");
    s.target_g = param(v, "sim.target_g");
    s.var_angle_rad2 = param(v, "sim.R");
    s.var_range_m2 = param(v, "sim.R_range");
    if (s.Ts_s > s.duration_s) return Error{"sim.Ts must not exceed sim.duration"};
    return radome::simulate(s);
  }

  static radome::FilterParams filter_params(const ParamValues& v) {
    radome::FilterParams fp;
    fp.Q = param(v, "Q");
    fp.tau_s = param(v, "tau");
    fp.var_angle = param(v, "R");
    fp.var_range = param(v, "R_range");
    fp.P0_pos_m2 = param(v, "P0_pos");
    fp.P0_vel_m2ps2 = param(v, "P0_vel");
    fp.P0_acc_m2ps4 = param(v, "P0_acc");
    fp.structure = param(v, "imm.structure") >= 0.5 ? radome::Structure::kFull
                                                    : radome::Structure::kAxisBlocks;
    fp.Kp = param(v, "Kp");
    fp.renewal = static_cast<radome::Renewal>(param(v, "renewal.mode"));
    fp.renewal_start_s = param(v, "renewal.start");
    fp.grid_min = param(v, "grid.min");
    fp.grid_max = param(v, "grid.max");
    fp.n_psi = static_cast<int>(param(v, "grid.n_psi"));
    fp.n_theta = static_cast<int>(param(v, "grid.n_theta"));
    fp.stay = param(v, "markov.stay");
    return fp;
  }

  Expected<std::shared_ptr<RunResult>> run_impl(const Dataset& d, const ParamValues& v,
                                                const RunControl& control) const override {
    if (auto st = params().check(v); !st) return st.err();
    if (auto st = require_columns(d, columns()); !st) return st.err();
    if (d.rows() < 2) return Error{d.source + ": need at least two rows"};
    const radome::FilterParams fp = filter_params(v);
    if (auto st = radome::check(fp); !st) return st.err();
    radome::Inputs in;
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
    auto rr = radome::run_radome_imm(in, fp, control);
    if (!rr) return Error{d.source + ": " + rr.error()};
    auto r = std::make_shared<radome::RadomeResult>(std::move(*rr));
    add_truth(*r, d);
    r->compute_nees();
    compute_metrics(*r, d);
    return std::shared_ptr<RunResult>(std::move(r));
  }

 private:
  static void add_truth(radome::RadomeResult& r, const Dataset& d) {
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
      r.alpha_true_deg[k] = radome::refraction_error(r.slope_psi_true[k], r.slope_theta_true[k],
                                                     psi_los[k], theta_los[k], pa[k], ta[k]) *
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

  static void compute_metrics(radome::RadomeResult& r, const Dataset& d) {
    Metrics& m = r.metrics;
    const std::size_t from = first_index_from(r.t, kMetricsFrom_s);
    m["slope_rmse_psi"] = rmse_finite(r.slope_psi, r.slope_psi_true, from);
    m["slope_rmse_theta"] = rmse_finite(r.slope_theta, r.slope_theta_true, from);
    m["slope_err_max_psi"] = max_abs_diff(r.slope_psi, r.slope_psi_true, from);
    m["slope_err_max_theta"] = max_abs_diff(r.slope_theta, r.slope_theta_true, from);
    m["refraction_err_max_deg"] = max_abs_diff(r.alpha_est_deg, r.alpha_true_deg, from);
    m["refraction_err_rmse_deg"] = rmse_finite(r.alpha_est_deg, r.alpha_true_deg, from);
    m["grid_center_psi_final"] = last_finite(r.center_psi);
    m["grid_center_theta_final"] = last_finite(r.center_theta);
    // Grid envelope: the furthest any grid edge reached (Fig. 9: about ±0.07 with Kp = 0.45).
    double lo_p = kNoSample, hi_p = kNoSample, lo_t = kNoSample, hi_t = kNoSample;
    const double op_lo = r.offsets_psi.front(), op_hi = r.offsets_psi.back();
    const double ot_lo = r.offsets_theta.front(), ot_hi = r.offsets_theta.back();
    for (std::size_t k = 0; k < r.steps(); ++k) {
      if (!std::isfinite(r.center_psi[k])) continue;
      const double a = r.center_psi[k] + op_lo, b = r.center_psi[k] + op_hi;
      const double c = r.center_theta[k] + ot_lo, e = r.center_theta[k] + ot_hi;
      if (!(lo_p <= a)) lo_p = a;
      if (!(hi_p >= b)) hi_p = b;
      if (!(lo_t <= c)) lo_t = c;
      if (!(hi_t >= e)) hi_t = e;
    }
    double cmax_p = 0.0, cmax_t = 0.0;
    for (std::size_t k = 0; k < r.steps(); ++k) {
      if (std::isfinite(r.center_psi[k])) cmax_p = std::max(cmax_p, std::abs(r.center_psi[k]));
      if (std::isfinite(r.center_theta[k])) cmax_t = std::max(cmax_t, std::abs(r.center_theta[k]));
    }
    // How far the grid reaches around the estimate (renewal: about its half-width).
    double span_p = 0.0, span_t = 0.0;
    for (std::size_t k = 0; k < r.steps(); ++k) {
      if (std::isfinite(r.center_psi[k]) && std::isfinite(r.slope_psi[k])) {
        const double c = r.center_psi[k] - r.slope_psi[k];
        span_p = std::max({span_p, std::abs(c + op_lo), std::abs(c + op_hi)});
      }
      if (std::isfinite(r.center_theta[k]) && std::isfinite(r.slope_theta[k])) {
        const double c = r.center_theta[k] - r.slope_theta[k];
        span_t = std::max({span_t, std::abs(c + ot_lo), std::abs(c + ot_hi)});
      }
    }
    m["grid_span_psi"] = span_p;
    m["grid_span_theta"] = span_t;
    m["grid_center_psi_max_abs"] = cmax_p;
    m["grid_center_theta_max_abs"] = cmax_t;
    m["grid_psi_min_reached"] = lo_p;
    m["grid_psi_max_reached"] = hi_p;
    m["grid_theta_min_reached"] = lo_t;
    m["grid_theta_max_reached"] = hi_t;
    // Measured-vs-true LOS difference (seed 001, Fig. 3: about ±2°).
    m["los_err_max_psi_deg"] = max_abs_diff(r.psi_meas_deg, r.psi_los_true_deg, 0);
    m["los_err_max_theta_deg"] = max_abs_diff(r.theta_meas_deg, r.theta_los_true_deg, 0);
    m["los_est_err_max_psi_deg"] = max_abs_diff(r.psi_los_est_deg, r.psi_los_true_deg, from);
    m["los_est_err_max_theta_deg"] = max_abs_diff(r.theta_los_est_deg, r.theta_los_true_deg, from);
    if (d.has("x_m")) {
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
    } else {
      for (const char* k : {"rmse", "rmse.x", "rmse.y", "rmse.z"})
        r.undefined.emplace(k, "no truth position (x_m, y_m, z_m) in the data");
    }
    // NIS of the 3-D pseudo-measurement over t ≥ 10 s, divided by its 3 dof.
    m["nis_mean"] = mean_finite(r.nis, from) / 3.0;
    m["nis_in_bounds"] = fraction_inside(
        std::vector<double>(
            r.nis.begin() + static_cast<std::ptrdiff_t>(std::min(from, r.nis.size())), r.nis.end()),
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

  // Why a radome metric has no value: the truth it compares against is missing, or the run
  // ends before the 10 s that the error metrics skip (anything else: finalize_run's reason).
  static void explain_undefined(radome::RadomeResult& r, const Dataset& d, std::size_t from) {
    auto has = [&](std::initializer_list<const char*> cols) {
      for (const char* c : cols) {
        if (!d.has(c) || count_finite(d.col(c)) == 0) return false;
      }
      return true;
    };
    const bool short_run = from >= r.steps();
    auto explain = [&](std::initializer_list<const char*> keys, bool truth, const std::string& why,
                       bool skips_start = true) {
      for (const char* k : keys) {
        auto it = r.metrics.find(k);
        if (it != r.metrics.end() && std::isfinite(it->second)) continue;
        if (!truth) {
          r.undefined.emplace(k, why);
        } else if (skips_start && short_run) {
          r.undefined.emplace(k, "the run ends within the first 10 s, which the metrics skip");
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
        r.undefined.emplace(k, "the run ends within the first 10 s, which the metrics skip");
    }
  }
};

}  // namespace

void register_scenario_radome(ScenarioRegistry& registry) {
  registry.add("radome", [] { return std::make_unique<RadomeScenario>(); });
}

}  // namespace kfw
