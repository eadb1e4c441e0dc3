// The `underwater` scenario (seed 004; docs/reproductions.md): sensor-measurement simulator with
// timing, correlation and outliers, its verifying statistics (`stats` command), and EKF
// localization with the AS / SC / SI update schemes.
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/scenario.h"
#include "core/statistics.h"
#include "filter/consistency.h"
#include "scenarios/underwater/underwater_ekf.h"
#include "scenarios/underwater/underwater_sim.h"
#include "scenarios/underwater/underwater_stats.h"

namespace kfw {

namespace {

using namespace underwater;

// A simulated log larger than this many rows is refused (memory, and the GUI re-runs it live).
constexpr double kMaxRows = 500000;

ParamTable make_table() {
  const std::string F = "Filter", S = "Simulator";
  ParamSpec scheme{
      "scheme",
      "update scheme",
      "",
      0,
      2,
      1,
      Scale::kChoice,
      F,
      "AS: each measurement when it arrives; SC: the ranges of a synchronous instant "
      "in one stacked update; SI: the same ranges one by one (Han et al. 2016, Table 13)."};
  scheme.choices = {"AS", "SC", "SI"};
  ParamSpec clock{
      "sim.clock",
      "sensor clocks",
      "",
      0,
      1,
      1,
      Scale::kChoice,
      S,
      "synchronous: one period sim.dt_sync for every sensor; asynchronous: Table 3 "
      "periods (DVL 0.20 s, AHRS 0.01 s, ranges 0.10 s, depth 0.02 s) (Han et al. 2016, "
      "Table 2)."};
  clock.choices = {"synchronous", "asynchronous"};
  return ParamTable({
      scheme,
      {"gate", "χ² gate d", "", 0.5, 50, 2.5, Scale::kLinear, F,
       "Reject a range when d = |z − ẑ|/√S exceeds it (Han et al. 2016, eq. 10: d = 2.5).", 2},
      {"sigma_range", "R: range σ_r", "m", 1e-3, 10, 0.1, Scale::kLog, F,
       "Range white-noise σ assumed by the filter."},
      {"sigma_depth", "R: depth σ_d", "m", 1e-3, 10, 0.2, Scale::kLog, F,
       "Depth noise σ assumed by the filter."},
      {"sigma_corr", "R: correlated range σ_c", "m", 1e-3, 5, 0.2, Scale::kLog, F,
       "Common range noise σ assumed by the filter (used when corr_in_R is on)."},
      {"corr_in_R", "correlated term in R", "", 0, 1, 1, Scale::kToggle, F,
       "SC: R = σ_r² I + σ_c² 1 1ᵀ; AS/SI: R = σ_r² + σ_c². Off: R = σ_r² I."},
      {"q_pos", "Q: position random walk q", "m/√s", 1e-4, 10, 0.07, Scale::kLog, F,
       "Dead-reckoning error growth, Q = q² Δt I."},
      {"sigma0_pos", "P0: initial position σ", "m", 1e-3, 100, 1.0, Scale::kLog, F,
       "Initial σ of x, y, z around (0, 0, first depth)."},
      {"sim.seed", "seed", "", 0, 1e6, 4, Scale::kInteger, S, "Random seed of the simulator."},
      {"sim.duration", "duration", "s", 1, 2400, 180, Scale::kLinear, S,
       "Length of the run (Han et al. 2016: 3 min). At most 40 min: the asynchronous clocks log "
       "195 "
       "rows/s, and a simulated log is limited to 500 000 rows.",
       0},
      clock,
      {"sim.dt_sync", "synchronous period Δt", "s", 0.01, 2, 0.1, Scale::kLinear, S,
       "Sample period of every sensor when the clocks are synchronous.", 3},
      {"sim.sigma_t", "timing jitter σ_t", "s", 0, 0.05, 0.001, Scale::kLinear, S,
       "t_{s,i} = t_{s,i−1} + Δt + n_t, n_t ~ N(0, σ_t) (Han et al. 2016, Table 2).", 4},
      {"sim.u_cmd", "command u", "m/s", -2, 2, 0.5, Scale::kLinear, S,
       "Surge velocity command (Han et al. 2016, Table 9).", 2},
      {"sim.w_cmd", "command w", "m/s", -1, 1, 0.2, Scale::kLinear, S,
       "Heave velocity command, positive down (Table 9).", 2},
      {"sim.r_cmd", "command r", "rad/s", -2, 2, 0.5, Scale::kLinear, S,
       "Yaw-rate command (Table 9).", 2},
      {"sim.motion_sigma_u", "motion noise σ_u", "m/s", 0, 1, 0.10, Scale::kLinear, S,
       "Gaussian noise on the actual surge velocity (Table 9).", 3},
      {"sim.motion_sigma_w", "motion noise σ_w", "m/s", 0, 1, 0.15, Scale::kLinear, S,
       "Gaussian noise on the actual heave velocity (Table 9).", 3},
      {"sim.motion_sigma_r", "motion noise σ_r", "rad/s", 0, 1, 0.10, Scale::kLinear, S,
       "Gaussian noise on the actual yaw rate (Table 9).", 3},
      {"sim.sigma_dvl_u", "DVL σ_u", "m/s", 0, 1, 0.1, Scale::kLinear, S,
       "DVL surge noise (Han et al. 2016, eq. 1, Table 10).", 3},
      {"sim.sigma_dvl_v", "DVL σ_v", "m/s", 0, 1, 0.0, Scale::kLinear, S,
       "DVL sway noise (Table 10: 0).", 3},
      {"sim.sigma_dvl_w", "DVL σ_w", "m/s", 0, 1, 0.1, Scale::kLinear, S,
       "DVL heave noise (Table 10).", 3},
      {"sim.sigma_yaw_rate", "AHRS σ_r", "rad/s", 0, 1, 0.1, Scale::kLinear, S,
       "AHRS yaw-rate noise (Table 10).", 3},
      {"sim.sigma_attitude", "AHRS attitude σ", "deg", 0, 5, 0.1, Scale::kLinear, S,
       "AHRS attitude noise (Table 11: resolution < 0.1°).", 3},
      {"sim.sigma_range", "range σ_r", "m", 0, 2, 0.1, Scale::kLinear, S,
       "Range white noise n_r (Han et al. 2016, eq. 2, Table 10); 0 switches it off.", 3},
      {"sim.sigma_depth", "depth σ_d", "m", 0, 2, 0.2, Scale::kLinear, S,
       "Depth noise n_d (eq. 3, Table 10); 0 switches it off.", 3},
      {"sim.sigma_corr", "correlated range σ_c", "m", 0, 2, 0.2, Scale::kLinear, S,
       "Common range noise n_c (Table 7: 0.2 high, 0.05 low); 0 switches it off.", 3},
      {"sim.t_gap", "correlation interval t_gap", "s", 0.01, 60, 1.0, Scale::kLinear, S,
       "n_c is redrawn every t_gap (Table 7: 1 s).", 2},
      {"sim.outliers", "outlier count N", "", 0, 10000, 276, Scale::kInteger, S,
       "Range samples drawn at random that get ±σ_o (Table 8; Table 14: 276); 0 = none."},
      {"sim.outlier_size", "outlier offset σ_o", "m", 0, 20, 1.0, Scale::kLinear, S,
       "Offset of an outlier, sign drawn at random (Han et al. 2016: ±1 m).", 2},
      {"sim.range_dropout", "range dropout", "", 0, 0.9, 0.0, Scale::kLinear, S,
       "Probability that a range sample is lost (an empty cell).", 3},
  });
}

SimParams sim_params(const ParamValues& v) {
  SimParams s;
  s.seed = static_cast<std::uint64_t>(param(v, "sim.seed"));
  s.duration_s = param(v, "sim.duration");
  s.synchronous = param(v, "sim.clock") == 0.0;
  s.dt_sync_s = param(v, "sim.dt_sync");
  s.sigma_t_s = param(v, "sim.sigma_t");
  s.command << param(v, "sim.u_cmd"), 0.0, param(v, "sim.w_cmd"), 0.0, 0.0, param(v, "sim.r_cmd");
  s.motion_sigma << param(v, "sim.motion_sigma_u"), 0.0, param(v, "sim.motion_sigma_w"), 0.0, 0.0,
      param(v, "sim.motion_sigma_r");
  s.velocity_sigma << param(v, "sim.sigma_dvl_u"), param(v, "sim.sigma_dvl_v"),
      param(v, "sim.sigma_dvl_w"), 0.0, 0.0, param(v, "sim.sigma_yaw_rate");
  s.attitude_sigma_rad = param(v, "sim.sigma_attitude") * std::numbers::pi / 180.0;
  s.sigma_range_m = param(v, "sim.sigma_range");
  s.sigma_depth_m = param(v, "sim.sigma_depth");
  s.sigma_corr_m = param(v, "sim.sigma_corr");
  s.t_gap_s = param(v, "sim.t_gap");
  s.outliers = static_cast<int>(param(v, "sim.outliers"));
  s.outlier_m = param(v, "sim.outlier_size");
  s.range_dropout = param(v, "sim.range_dropout");
  return s;
}

FilterParams filter_params(const ParamValues& v) {
  FilterParams f;
  f.scheme = static_cast<Scheme>(static_cast<int>(param(v, "scheme")));
  f.gate = param(v, "gate");
  f.sigma_range_m = param(v, "sigma_range");
  f.sigma_depth_m = param(v, "sigma_depth");
  f.sigma_corr_m = param(v, "sigma_corr");
  f.corr_in_R = param(v, "corr_in_R") != 0.0;
  f.q_pos = param(v, "q_pos");
  f.sigma0_pos_m = param(v, "sigma0_pos");
  return f;
}

nlohmann::json matrix_json(const Covariance<kErrorDims>& M) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < kErrorDims; ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (int j = 0; j < kErrorDims; ++j)
      row.push_back(M(i, j));
    rows.push_back(row);
  }
  return rows;
}

// Means of the range variances, range–range covariances and range–depth covariances.
void summarise(const Covariance<kErrorDims>& C, double& var, double& cov, double& depth_cov) {
  var = cov = depth_cov = 0.0;
  for (int i = 0; i < kBeacons; ++i) {
    var += C(i, i) / kBeacons;
    depth_cov += C(i, kBeacons) / kBeacons;
    for (int j = 0; j < kBeacons; ++j) {
      if (i != j) cov += C(i, j) / (kBeacons * (kBeacons - 1));
    }
  }
}

// The underwater metrics beyond the shared vocabulary.
std::vector<MetricSpec> make_metric_specs() {
  using G = MetricGroup;
  using D = Direction;
  return {
      // The shared `rmse`, made specific: the distance error is a compound of x, y and z.
      {"rmse", "RMSE of the position", "m",
       "RMS of the distance between estimated and true position, every row with truth (seed "
       "004, Table 13)",
       G::kAccuracy, D::kLower},
      {"pos_mean", "mean distance error", "m",
       "mean distance between estimated and true position (Han et al. 2016, Table 13)",
       G::kAccuracy, D::kLower},
      {"pos_std", "std of the distance error", "m",
       "standard deviation of the distance between estimated and true position", G::kAccuracy,
       D::kLower},
      {"pos_max", "largest distance error", "m",
       "largest distance between estimated and true position", G::kAccuracy, D::kLower},
      {"outliers_injected", "outliers injected", "",
       "range samples the simulator offset by ±sim.outlier_size (from the outlier1..4 columns)",
       G::kScenario, D::kLower},
      {"outliers_detected", "outliers detected", "",
       "injected outliers that the χ² gate rejected (Han et al. 2016, Table 14)", G::kScenario,
       D::kHigher},
      {"outliers_false_alarm", "false alarms", "", "good range samples that the χ² gate rejected",
       G::kScenario, D::kLower},
      {"ranges_used", "ranges used", "", "range samples that went into an update", G::kScenario,
       D::kHigher},
      {"ranges_rejected", "ranges rejected", "", "range samples that the χ² gate rejected",
       G::kScenario, D::kLower},
      {"ranges_invalid", "ranges invalid", "",
       "range samples that could not be used (range ≤ 0, or S not positive definite)", G::kScenario,
       D::kLower},
      {"depth_used", "depth samples used", "", "depth samples that went into an update",
       G::kScenario, D::kHigher},
      {"steps", "steps", "", "number of rows (sensor times) in the run", G::kScenario, D::kNone},
      {"stats_range_var_mean", "range-error variance (mean)", "m²",
       "sample variance of the range errors at synchronous instants, mean over the four beacons "
       "(Han et al. 2016, eq. 5–8)",
       G::kScenario, D::kLower},
      {"stats_range_cov_mean", "range–range covariance (mean)", "m²",
       "sample covariance between the range errors of two beacons, mean over the pairs (seed "
       "004, eq. 6–8: σ_c²)",
       G::kScenario, D::kLower},
      {"stats_depth_var", "depth-error variance", "m²",
       "sample variance of the depth error at synchronous instants (Han et al. 2016, eq. 5)",
       G::kScenario, D::kLower},
      {"stats_instants", "synchronous instants", "",
       "instants with every range and the depth, over which the statistics are taken", G::kScenario,
       D::kHigher},
  };
}

class UnderwaterScenario final : public Scenario {
 public:
  std::string name() const override { return "underwater"; }
  std::vector<MetricSpec> metric_specs() const override {
    static const std::vector<MetricSpec> specs = make_metric_specs();
    return specs;
  }
  std::string title() const override {
    return "Underwater vehicle: sensor simulator + EKF localization AS/SC/SI (Han et al. 2016)";
  }
  const ParamTable& params() const override {
    static const ParamTable table = make_table();
    return table;
  }
  std::vector<ColumnSpec> columns() const override {
    return {{"t", "s", "measurement time", true},
            {"dvl_u", "m/s", "DVL surge velocity; empty = no sample", true},
            {"dvl_v", "m/s", "DVL sway velocity", true},
            {"dvl_w", "m/s", "DVL heave velocity (down)", true},
            {"ahrs_phi", "rad", "AHRS roll", false},
            {"ahrs_theta", "rad", "AHRS pitch", false},
            {"ahrs_psi", "rad", "AHRS heading; empty = no sample", true},
            {"ahrs_p", "rad/s", "AHRS roll rate", false},
            {"ahrs_q", "rad/s", "AHRS pitch rate", false},
            {"ahrs_r", "rad/s", "AHRS yaw rate", false},
            {"range1", "m", "range to beacon 1; empty = no sample", true},
            {"range2", "m", "range to beacon 2", true},
            {"range3", "m", "range to beacon 3", true},
            {"range4", "m", "range to beacon 4", true},
            {"depth", "m", "depth (z, down)", true},
            {"x_true", "m", "true x (north)", false},
            {"y_true", "m", "true y (east)", false},
            {"z_true", "m", "true z (down)", false},
            {"psi_true", "rad", "true heading", false},
            {"x_cmd", "m", "command trajectory x", false},
            {"y_cmd", "m", "command trajectory y", false},
            {"z_cmd", "m", "command trajectory z", false},
            {"outlier1", "m", "injected outlier offset on range1 (0 = clean)", false},
            {"outlier2", "m", "injected outlier offset on range2", false},
            {"outlier3", "m", "injected outlier offset on range3", false},
            {"outlier4", "m", "injected outlier offset on range4", false}};
  }

  Expected<Dataset> simulate(const ParamValues& v) const override {
    if (auto st = params().check(v); !st) return st.err();
    const SimParams s = sim_params(v);
    double rows = s.duration_s / s.dt_sync_s;
    if (!s.synchronous) {
      rows = 0.0;
      for (double dt : s.period_s)
        rows += s.duration_s / dt;
    }
    if (rows > kMaxRows) {
      return Error{"sim.duration: " + std::to_string(static_cast<long>(rows)) +
                   " rows would exceed the limit of " +
                   std::to_string(static_cast<long>(kMaxRows)) +
                   "; shorten the run or use synchronous clocks (sim.clock) with a longer "
                   "sim.dt_sync"};
    }
    return underwater::simulate(s);
  }

  Expected<std::shared_ptr<RunResult>> run_impl(const Dataset& d, const ParamValues& v,
                                                const RunControl& control) const override {
    if (auto st = params().check(v); !st) return st.err();
    auto res = run_ekf(d, filter_params(v), control);
    if (!res) return res.err();
    auto r = std::make_shared<UnderwaterResult>(std::move(*res));
    r->design = design_covariance(param(v, "sim.sigma_range"), param(v, "sim.sigma_corr"),
                                  param(v, "sim.sigma_depth"));
    Metrics& m = r->metrics;
    const char* const kStats[] = {"stats_range_var_mean", "stats_range_cov_mean", "stats_depth_var",
                                  "stats_instants"};
    const std::string no_truth = "no truth position (x_true, y_true, z_true) in the data";
    if (d.has("x_true") && d.has("y_true") && d.has("z_true")) {
      auto st = error_stats(d);
      if (st) {
        r->has_stats = true;
        r->stats = *st;
        double var = 0, cov = 0, dcov = 0;
        summarise(st->covariance, var, cov, dcov);
        m["stats_range_var_mean"] = var;
        m["stats_range_cov_mean"] = cov;
        m["stats_depth_var"] = st->covariance(kBeacons, kBeacons);
        m["stats_instants"] = static_cast<double>(st->instants);
      } else {
        r->warnings.push_back("statistics: " + st.error());
        for (const char* k : kStats)
          r->undefined.emplace(k, "statistics: " + st.error());
      }
    } else {
      for (const char* k : kStats)
        r->undefined.emplace(k, no_truth);
    }
    // Distance error over every row with truth (seed 004, Table 13).
    std::vector<double> e;
    e.reserve(r->pos_err.size());
    for (double x : r->pos_err) {
      if (std::isfinite(x)) e.push_back(x);
    }
    double mean = kNoSample, sd = kNoSample, mx = kNoSample, rmse = kNoSample;
    if (!e.empty()) {
      double s = 0, s2 = 0;
      mx = 0;
      for (double x : e) {
        s += x;
        s2 += x * x;
        mx = std::max(mx, x);
      }
      const double nn = static_cast<double>(e.size());
      mean = s / nn;
      rmse = std::sqrt(s2 / nn);
      sd = e.size() > 1 ? std::sqrt(std::max(0.0, (s2 - nn * mean * mean) / (nn - 1))) : 0.0;
    }
    m["pos_mean"] = mean;
    m["pos_std"] = sd;
    m["pos_max"] = mx;
    m["rmse"] = rmse;
    if (e.empty()) {
      for (const char* k : {"rmse", "pos_mean", "pos_std", "pos_max"})
        r->undefined.emplace(k, no_truth);
    }
    // Without the injected-outlier columns these are unknown, not zero.
    auto known = [&](std::size_t count) {
      return r->outliers_known ? static_cast<double>(count) : kNoSample;
    };
    if (!r->outliers_known) {
      for (const char* k : {"outliers_injected", "outliers_detected", "outliers_false_alarm"})
        r->undefined.emplace(k, "no injected-outlier columns (outlier1..4) in the data");
    }
    m["outliers_injected"] = known(r->outliers_injected);
    m["outliers_detected"] = known(r->outliers_detected);
    m["outliers_false_alarm"] = known(r->outliers_false_alarm);
    m["ranges_used"] = static_cast<double>(r->ranges_used);
    m["ranges_rejected"] = static_cast<double>(r->ranges_rejected);
    m["ranges_invalid"] = static_cast<double>(r->ranges_invalid);
    m["depth_used"] = static_cast<double>(r->depth_used);
    m["steps"] = static_cast<double>(r->steps());
    add_consistency_metrics(r->channels(), r->nees_series(), m, r->undefined);
    return std::shared_ptr<RunResult>(std::move(r));
  }

  std::vector<std::string> commands() const override { return {"stats"}; }

  // `kfw-cli stats underwater --data FILE.csv`: seed 004, Sec. 4.1–4.3 (eq. 5–9) and Table 14.
  Expected<std::string> command(const std::string& cmd, const Dataset& d,
                                const ParamValues& v) const override {
    if (cmd != "stats") return Scenario::command(cmd, d, v);
    if (auto st = params().check(v); !st) return st.err();
    auto st = error_stats(d);
    if (!st) return st.err();
    auto run_result = run_ekf(d, filter_params(v));
    if (!run_result) return run_result.err();
    nlohmann::json j;
    j["source"] = d.source;
    j["labels"] = kErrorLabels;
    j["instants"] = st->instants;
    j["outlier_instants"] = st->outlier_instants;
    j["covariance"] = matrix_json(st->covariance);
    j["design"] = matrix_json(design_covariance(
        param(v, "sim.sigma_range"), param(v, "sim.sigma_corr"), param(v, "sim.sigma_depth")));
    j["mean"] = {st->mean(0), st->mean(1), st->mean(2), st->mean(3), st->mean(4)};
    double var = 0, cov = 0, dcov = 0;
    summarise(st->covariance, var, cov, dcov);
    j["range_var_mean"] = var;
    j["range_cov_mean"] = cov;
    j["range_depth_cov_mean"] = dcov;
    j["depth_var"] = st->covariance(kBeacons, kBeacons);
    // Unknown (null) without the injected-outlier columns.
    if (run_result->outliers_known) {
      j["outliers_injected"] = st->outliers_injected;
      j["outliers_detected"] = run_result->outliers_detected;
      j["outliers_false_alarm"] = run_result->outliers_false_alarm;
    } else {
      j["outliers_injected"] = j["outliers_detected"] = j["outliers_false_alarm"] = nullptr;
    }
    j["scheme"] = params().format("scheme", param(v, "scheme"));
    j["gate"] = param(v, "gate");
    return j.dump(2);
  }
};

}  // namespace

void register_scenario_underwater(ScenarioRegistry& registry) {
  registry.add("underwater", [] { return std::make_unique<UnderwaterScenario>(); });
}

}  // namespace kfw
