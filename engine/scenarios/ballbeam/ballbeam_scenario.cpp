// The `ballbeam` scenario (seed 003; docs/reproductions.md): parameter table, schema, simulator and
// runner.
#include <cmath>
#include <memory>
#include <sstream>
#include <string>

#include "core/scenario.h"
#include "core/statistics.h"
#include "filter/consistency.h"
#include "scenarios/ballbeam/alpha_beta.h"
#include "scenarios/ballbeam/ball_tracker.h"
#include "scenarios/ballbeam/ballbeam_loop.h"
#include "scenarios/ballbeam/ballbeam_result.h"

namespace kfw {

namespace {

using namespace ballbeam;

constexpr double kClosed = 0.0;  // `mode` choice indices
constexpr double kReplay = 1.0;

ParamTable make_table() {
  const std::string F = "Filter", S = "Simulator";
  ParamSpec filter{"filter",
                   "filter",
                   "",
                   0,
                   1,
                   1,
                   Scale::kChoice,
                   F,
                   "kf: time-varying Kalman filter (eq. 14–15); steady: α-β filter with the "
                   "closed-form gain of eq. 16."};
  filter.choices = {"kf", "steady"};
  ParamSpec mode{"mode",
                 "run mode",
                 "",
                 0,
                 1,
                 0,
                 Scale::kChoice,
                 F,
                 "closed: re-simulate the closed loop from the sim.* parameters (noise-free, "
                 "detection on and off); replay: filter the dataset's recorded x_meas/v_sensor."};
  mode.choices = {"closed", "replay"};
  return ParamTable({
      {"Q", "Q, ball acceleration noise variance", "(m/s²)²", 1e-8, 1e6, 0.5013, Scale::kLog, F,
       "w ~ N(0, Q) in x_{k+1} = F x_k + G^c u^c_k + G w_k (Jang et al. 2014, eq. 12–13). 0.5013 "
       "with "
       "R = 4e-6 m², Ts = 10 ms gives λ = 0.0354, Table 1's α = 0.234, β = 0.031.",
       4},
      {"R", "R, position noise variance", "m²", 1e-12, 1.0, 4e-6, Scale::kLog, F,
       "v ~ N(0, R) on the ball position reading (Jang et al. 2014, eq. 13)."},
      {"Ts", "Ts, sample period", "s", 0.001, 0.1, 0.01, Scale::kLinear, F,
       "Period of sensor, filter and controller (not stated in Jang et al. 2014; 10 ms chosen). "
       "Replay uses the dataset's period.",
       3},
      filter,
      {"detection", "impulsive-noise detection circuit", "", 0, 1, 1, Scale::kToggle, F,
       "On: samples where the circuit outputs 0 V are missing data (update skipped). Off: the "
       "impulsive readings go into the filter (Fig. 9)."},
      mode,
      {"sim.seed", "seed", "", 0, 1e6, 3, Scale::kInteger, S, "Random seed of the simulator."},
      {"sim.duration", "duration", "s", 2, 600, 15, Scale::kLinear, S, "Length of the run.", 1},
      {"sim.setpoint", "set-point step x_c", "m", -0.15, 0.15, 0.1, Scale::kLinear, S,
       "Ball set-point after the step (0 before).", 3},
      {"sim.step_time", "step time", "s", 0, 100, 1, Scale::kLinear, S,
       "Instant of the set-point step; must lie inside the run.", 2},
      {"sim.x0", "initial ball position", "m", -0.15, 0.15, 0.0, Scale::kLinear, S,
       "Ball at rest here at t = 0; the filter starts here too.", 3},
      {"sim.sigma_pos", "σ position reading", "m", 0, 0.05, 0.002, Scale::kLinear, S,
       "Gaussian reading noise while the ball touches the wire.", 4},
      {"sim.contact_loss_rate", "contact-loss rate", "", 0, 1, 0.05, Scale::kLinear, S,
       "Probability per sample that the ball starts losing contact with the wire.", 3},
      {"sim.burst", "contact-loss burst length", "samples", 1, 100, 3, Scale::kInteger, S,
       "Mean length of a contact loss (geometric); each lost sample reads an impulsive spike "
       "anywhere along the beam."},
      {"sim.V_max", "motor voltage limit", "V", 1, 1000, 12, Scale::kLog, S,
       "Amplifier saturation |V| ≤ V_max (not in Jang et al. 2014; 12 V chosen for a small DC "
       "motor)."},
      {"sim.theta_max", "beam angle stop θ_max", "rad", 0.05, 1.5, 0.785, Scale::kLinear, S,
       "Mechanical stops |θ| ≤ θ_max (not in Jang et al. 2014; 45° assumed). The model ẍ = a3 θ "
       "assumes small angles; beyond 0.25 rad the run warns.",
       3},
  });
}

// A number as a user would write it (no trailing zeros).
std::string num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// The ball has rolled off the beam: in the closed loop it falls and the run stops there.
std::string left_beam_warning(double t_s, double half_length_m, const std::string& variant,
                              bool fell) {
  return "ball off the beam (|x| > " + num(half_length_m) + " m) at t = " + num(t_s) + " s (" +
         variant + (fell ? "); it fell off, the run stops there" : ")");
}

bool is_simulated(const Dataset& d) {
  return d.source.rfind("simulated ballbeam", 0) == 0;
}

// The ballbeam metrics beyond the shared vocabulary (rmse is the ball position x).
std::vector<MetricSpec> make_metric_specs() {
  using G = MetricGroup;
  using D = Direction;
  std::vector<MetricSpec> v = {
      {"tracking_rmse", "tracking RMSE", "m",
       "RMS of the true ball position minus the set-point after the step (closed loop: the run "
       "with the chosen detection; replay: the logged truth)",
       G::kAccuracy, D::kLower},
      {"left_beam_at_s", "ball off the beam at", "s",
       "first time the true ball is beyond a beam end (±0.2 m); undefined while it stays on",
       G::kScenario, D::kHigher},
      {"diverged", "closed loop diverged", "", "1 when the closed loop diverged, else 0",
       G::kScenario, D::kLower},
      {"fell", "ball fell off", "",
       "1 when the ball fell off a beam end (the run stops there), else 0; its mean over seeds "
       "is the fraction that fell",
       G::kScenario, D::kLower},
      {"tracking_excess", "tracking excess over noise-free", "m",
       "RMS of x − x_noise-free: the true ball position against the same closed loop without "
       "sensor noise and contact loss, over the run (up to a fall)",
       G::kAccuracy, D::kLower},
      {"tracking_excess_detect_on", "tracking excess, detection on", "m",
       "RMS of x − x_noise-free with detection on, up to a fall", G::kAccuracy, D::kLower},
      {"tracking_excess_detect_off", "tracking excess, detection off", "m",
       "RMS of x − x_noise-free with detection off, up to a fall", G::kAccuracy, D::kLower},
      {"alpha", "α (closed form)", "", "α of the α-β filter from λ (Jang et al. 2014, eq. 16)",
       G::kGains, D::kNone},
      {"beta", "β (closed form)", "", "β of the α-β filter from λ (Jang et al. 2014, eq. 16)",
       G::kGains, D::kNone},
      {"lambda", "λ, tracking index", "", "λ = Ts² √(Q/R) (Jang et al. 2014, eq. 16)", G::kGains,
       D::kNone},
      {"alpha_dare", "α (DARE)", "", "steady-state K1 of the same model from the DARE", G::kGains,
       D::kNone},
      {"beta_dare", "β (DARE)", "", "steady-state K2·Ts of the same model from the DARE", G::kGains,
       D::kNone},
      {"missing_fraction", "samples with contact lost", "",
       "fraction of the samples read while the ball had lost contact with the wire", G::kScenario,
       D::kLower},
      {"skipped_fraction", "updates skipped", "",
       "fraction of the samples whose update the filter skipped (flagged or missing)", G::kScenario,
       D::kLower},
      {"K1_final", "settled K1", "",
       "position gain at the end of the longest unbroken run of updates (α for filter=steady)",
       G::kGains, D::kNone},
      {"K2_final_times_Ts", "settled K2·Ts", "",
       "velocity gain times Ts at the end of the longest unbroken run of updates (β for "
       "filter=steady)",
       G::kGains, D::kNone},
      {"K_final_run", "updates in the settled run", "",
       "length of the longest unbroken run of updates, where K1_final is read", G::kScenario,
       D::kHigher},
      {"steps", "steps", "", "number of samples in the run", G::kScenario, D::kNone},
      {"Ts", "sample period", "s", "sample period of sensor, filter and controller", G::kScenario,
       D::kNone},
  };
  // The closed loop runs three ways with the same seed; each reports the same figures.
  const std::pair<const char*, const char*> variants[] = {{"_noise_free", "noise-free"},
                                                          {"_detect_on", "detection on"},
                                                          {"_detect_off", "detection off"}};
  for (const auto& [suffix, name] : variants) {
    const std::string s = suffix, n = name;
    v.push_back({"rmse_pos" + s, "position RMSE, " + n, "m",
                 "RMSE of the estimated ball position against truth, closed loop " + n,
                 G::kAccuracy, D::kLower});
    v.push_back(
        {"tracking_rmse" + s, "tracking RMSE, " + n, "m",
         "RMS of the true ball position minus the set-point after the step, closed loop " + n,
         G::kAccuracy, D::kLower});
    v.push_back({"max_abs_pos" + s, "largest |x|, " + n, "m",
                 "largest distance of the true ball from the beam centre, closed loop " + n,
                 G::kScenario, D::kLower});
    v.push_back({"max_abs_theta" + s, "largest |θ|, " + n, "rad",
                 "largest beam angle, closed loop " + n, G::kScenario, D::kLower});
    v.push_back({"V_rms" + s, "RMS motor voltage, " + n, "V",
                 "RMS of the motor voltage, closed loop " + n, G::kScenario, D::kLower});
    v.push_back({"left_beam_at_s" + s, "ball off the beam at, " + n, "s",
                 "first time the true ball is beyond a beam end, closed loop " + n +
                     "; undefined while it stays on",
                 G::kScenario, D::kHigher});
  }
  return v;
}

class BallbeamScenario final : public Scenario {
 public:
  std::string primary_state() const override { return "x"; }
  std::vector<MetricSpec> metric_specs() const override {
    static const std::vector<MetricSpec> specs = make_metric_specs();
    return specs;
  }
  std::string name() const override { return "ballbeam"; }
  std::string title() const override {
    return "Ball and beam: steady-state KF / α-β with missing data, closed loop (Jang et al. 2014)";
  }
  const ParamTable& params() const override {
    static const ParamTable table = make_table();
    return table;
  }
  std::optional<DataUnused> data_unused(const ParamValues& v) const override {
    if (param(v, "mode") != kClosed) return std::nullopt;
    return DataUnused{"mode=closed re-simulates the loop from the Simulator parameters",
                      "mode=replay"};
  }

  std::vector<ColumnSpec> columns() const override {
    return {{"t", "s", "time", true},
            {"x_meas", "m",
             "raw ball position reading (impulsive while contact is lost); empty = "
             "no sample",
             true},
            {"v_sensor", "V", "discrimination-circuit output, exactly 0 V = contact lost", false},
            {"v_raw", "V", "sensor voltage without the circuit", false},
            {"theta", "rad", "beam angle (input u^c = a3 θ of the tracking filter)", false},
            {"setpoint", "m", "ball set-point x_c", false},
            {"truth", "m", "true ball position", false},
            {"v_truth", "m/s", "true ball velocity", false}};
  }

  static Expected<LoopParams> loop_params(const ParamValues& v) {
    LoopParams p;
    p.Ts_s = param(v, "Ts");
    p.duration_s = param(v, "sim.duration");
    p.step_time_s = param(v, "sim.step_time");
    p.setpoint_m = param(v, "sim.setpoint");
    p.x0_m = param(v, "sim.x0");
    p.sigma_pos_m = param(v, "sim.sigma_pos");
    p.contact_loss_rate = param(v, "sim.contact_loss_rate");
    p.burst = static_cast<int>(param(v, "sim.burst"));
    p.seed = static_cast<std::uint64_t>(param(v, "sim.seed"));
    p.V_max = param(v, "sim.V_max");
    p.theta_max_rad = param(v, "sim.theta_max");
    if (p.duration_s / p.Ts_s > 2e6)
      return Error{"sim.duration / Ts exceeds 2 million samples; raise Ts or shorten the run"};
    return p;
  }

  static Expected<BallTracker> tracker(const ParamValues& v, double Ts_s) {
    TrackerParams tp;
    tp.Ts_s = Ts_s;
    tp.Q = param(v, "Q");
    tp.R = param(v, "R");
    tp.kind = param(v, "filter") == 0 ? FilterKind::kKalman : FilterKind::kSteady;
    auto t = BallTracker::make(tp);
    if (!t) return Error{"filter: " + t.error()};
    return t;
  }

  Expected<Dataset> simulate(const ParamValues& v) const override {
    if (auto st = params().check(v); !st) return st.err();
    auto lp = loop_params(v);
    if (!lp) return lp.err();
    auto tr = tracker(v, lp->Ts_s);
    if (!tr) return tr.err();
    const Disturbances d = make_disturbances(loop_steps(*lp), *lp);
    LoopOptions opt;
    opt.detection = param(v, "detection") != 0;
    const LoopTrace trace = run_closed_loop(*lp, *tr, d, opt);
    if (trace.diverged)
      return Error{"the closed loop diverged at t = " + num(trace.diverged_at_s) +
                   " s (Ts too long for Table 1's gains?)"};
    return to_dataset(trace, "simulated ballbeam, seed " + std::to_string(lp->seed));
  }

  Expected<std::shared_ptr<RunResult>> run_impl(const Dataset& d, const ParamValues& v,
                                                const RunControl& control) const override {
    if (auto st = params().check(v); !st) return st.err();
    auto r = std::make_shared<BallbeamResult>();
    const bool detection = param(v, "detection") != 0;
    if (param(v, "mode") == kClosed) {
      auto lp = loop_params(v);
      if (!lp) return lp.err();
      auto tr = tracker(v, lp->Ts_s);
      if (!tr) return tr.err();
      if (d.rows() > 0 && !is_simulated(d))
        r->warnings.push_back(
            "mode=closed re-simulates the loop from the sim.* parameters; the "
            "dataset '" +
            d.source + "' is not filtered (use mode=replay)");
      const Disturbances dist = make_disturbances(loop_steps(*lp), *lp);
      LoopOptions on, off, clean;
      off.detection = false;
      clean.impulsive = false;
      LoopTrace t_on = run_closed_loop(*lp, *tr, dist, on, control);
      if (control.cancelled()) return Error{"cancelled"};
      LoopTrace t_off = run_closed_loop(*lp, *tr, dist, off, control);
      if (control.cancelled()) return Error{"cancelled"};
      const LoopTrace t_clean = run_closed_loop(*lp, *tr, dist, clean, control);
      if (control.cancelled()) return Error{"cancelled"};
      r->closed_loop = true;
      // Each variant on the whole loop's time grid (NaN after it fell).
      const std::size_t n_loop = loop_steps(*lp);
      r->t_loop.resize(n_loop);
      for (std::size_t k = 0; k < n_loop; ++k)
        r->t_loop[k] = static_cast<double>(k) * lp->Ts_s;
      auto padded = [&](std::vector<double> x) {
        x.resize(n_loop, kNoSample);
        return x;
      };
      r->x_noise_free = padded(t_clean.x_true);
      r->x_detect_on = padded(t_on.x_true);
      r->x_detect_off = padded(t_off.x_true);
      r->x_hat_detect_on = padded(t_on.x_hat);
      r->x_hat_detect_off = padded(t_off.x_hat);
      r->step_time_s = lp->step_time_s;
      if (lp->step_time_s >= lp->duration_s)
        r->warnings.push_back("sim.step_time (" + num(lp->step_time_s) +
                              " s) is not before the end of the run (sim.duration = " +
                              num(lp->duration_s) + " s): the set point stays at 0");
      Metrics& m = r->metrics;
      const double half_m = lp->sensor.half_length_m();
      auto variant = [&](const LoopTrace& t, const std::string& suffix, const std::string& label) {
        const std::size_t from = first_index_at(t.t, lp->step_time_s);
        m["rmse_pos" + suffix] = rmse_finite(t.x_hat, t.x_true);
        m["tracking_rmse" + suffix] = rmse_finite(t.x_true, t.setpoint, from);
        // No sample at or after the step: the set point never moved in this run (a step at or
        // after sim.duration), or the ball left the beam before it.
        if (from >= t.t.size()) {
          r->undefined.emplace(
              "tracking_rmse" + suffix,
              t.fell && lp->step_time_s < lp->duration_s
                  ? "the ball left the beam at t = " + num(t.left_beam_at_s) +
                        " s, before the set-point step at " + num(lp->step_time_s) + " s"
                  : "no sample after the set-point step (sim.step_time = " + num(lp->step_time_s) +
                        " s, the run ends at " + num(lp->duration_s) + " s)");
        }
        m["max_abs_pos" + suffix] = max_abs(t.x_true);
        m["max_abs_theta" + suffix] = max_abs(t.theta);
        m["V_rms" + suffix] = std::sqrt(mean_square(t.V));
        m["left_beam_at_s" + suffix] = t.left_beam_at_s;
        if (!std::isfinite(t.left_beam_at_s))
          r->undefined.emplace("left_beam_at_s" + suffix, "the ball stayed on the beam");
        if (std::isfinite(t.left_beam_at_s))
          r->warnings.push_back(left_beam_warning(t.left_beam_at_s, half_m, label, t.fell));
        if (m["max_abs_theta" + suffix] > kSmallAngleRad) {
          r->warnings.push_back("beam angle reached " + num(m["max_abs_theta" + suffix]) +
                                " rad (" + label + "); the model ẍ = a3 θ assumes small angles (" +
                                num(kSmallAngleRad) + " rad)");
        }
        if (t.diverged)
          r->warnings.push_back("closed loop (" + label +
                                ") diverged at t = " + num(t.diverged_at_s) + " s");
      };
      variant(t_clean, "_noise_free", "noise-free");
      variant(t_on, "_detect_on", "detection on");
      variant(t_off, "_detect_off", "detection off");
      // Up to a fall: the fallen run has no samples after it.
      m["tracking_excess_detect_on"] = rmse_finite(t_on.x_true, t_clean.x_true);
      m["tracking_excess_detect_off"] = rmse_finite(t_off.x_true, t_clean.x_true);
      r->detection_on = detection;
      r->trace = detection ? std::move(t_on) : std::move(t_off);
      const std::string chosen = detection ? "tracking_rmse_detect_on" : "tracking_rmse_detect_off";
      m["tracking_rmse"] = m[chosen];
      if (auto it = r->undefined.find(chosen); it != r->undefined.end())
        r->undefined.emplace("tracking_rmse", it->second);
      m["tracking_excess"] =
          m[detection ? "tracking_excess_detect_on" : "tracking_excess_detect_off"];
      m["fell"] = r->trace.fell ? 1.0 : 0.0;
      m["left_beam_at_s"] = r->trace.left_beam_at_s;
      if (!std::isfinite(r->trace.left_beam_at_s))
        r->undefined.emplace("left_beam_at_s", "the ball stayed on the beam");
      m["diverged"] = r->trace.diverged ? 1.0 : 0.0;
    } else {
      if (auto st = require_columns(d, columns()); !st) return st.err();
      if (d.rows() < 2) return Error{d.source + ": need at least two rows"};
      const double Ts = d.median_dt();
      if (!(Ts > 0.0) || !std::isfinite(Ts))
        return Error{d.source + ": column 't' must increase; its median sample period is " +
                     num(Ts) + " s"};
      auto tr = tracker(v, Ts);
      if (!tr) return tr.err();
      if (std::abs(Ts - param(v, "Ts")) > 1e-9 * Ts)
        r->warnings.push_back("replay uses the dataset's sample period " + num(Ts) +
                              " s, not Ts = " + num(param(v, "Ts")) + " s");
      const auto* vs = d.has("v_sensor") ? &d.col("v_sensor") : nullptr;
      const auto* th = d.has("theta") ? &d.col("theta") : nullptr;
      r->trace = replay(d.col("t"), d.col("x_meas"), vs, th, *tr, detection, Plant{}.a3, control);
      if (control.cancelled()) return Error{"cancelled"};
      r->closed_loop = false;
      if (d.has("truth")) r->trace.x_true = d.col("truth");
      if (d.has("v_truth")) r->trace.v_true = d.col("v_truth");
      if (d.has("setpoint")) r->trace.setpoint = d.col("setpoint");
      if (d.has("v_raw")) r->trace.v_raw = d.col("v_raw");
      Metrics& m = r->metrics;
      std::size_t from = 0;
      const auto& sp = r->trace.setpoint;
      while (from < sp.size() && sp[from] == sp.front())
        ++from;
      if (from == sp.size()) from = 0;
      r->step_time_s = from < r->trace.t.size() ? r->trace.t[from] : 0.0;
      m["tracking_rmse"] = rmse_finite(r->trace.x_true, sp, from);
      const bool has_truth = count_finite(r->trace.x_true) > 0;
      if (!has_truth) {
        r->undefined.emplace("tracking_rmse", "no truth column ('truth') in the data");
      } else if (count_finite(sp) == 0) {
        r->undefined.emplace("tracking_rmse", "no set-point column ('setpoint') in the data");
      }
      const double half_m = SensorModel{}.half_length_m();
      r->trace.left_beam_at_s = left_beam_at(r->trace.t, r->trace.x_true, half_m);
      m["left_beam_at_s"] = r->trace.left_beam_at_s;
      if (!std::isfinite(r->trace.left_beam_at_s))
        r->undefined.emplace("left_beam_at_s", has_truth ? "the ball stayed on the beam"
                                                         : "no truth column ('truth') in the data");
      if (std::isfinite(r->trace.left_beam_at_s))
        r->warnings.push_back(
            left_beam_warning(r->trace.left_beam_at_s, half_m, "logged truth", false));
    }
    r->t = r->trace.t;
    const LoopTrace& tr = r->trace;
    const auto track =
        tracker(v, tr.t.size() >= 2 && !r->closed_loop ? d.median_dt() : param(v, "Ts"));
    r->Ts_s = track->params().Ts_s;
    r->lambda = track->lambda();
    r->alpha = track->gains().alpha;
    r->beta = track->gains().beta;
    auto ss = steady_gain_dare(r->Ts_s, param(v, "Q"), param(v, "R"));
    r->alpha_dare = ss ? ss->alpha : kNoSample;
    r->beta_dare = ss ? ss->beta : kNoSample;
    if (!ss) {
      r->warnings.push_back("steady-state gain: " + ss.error());
      for (const char* k : {"alpha_dare", "beta_dare"})
        r->undefined.emplace(k, "the DARE failed: " + ss.error());
    }

    Metrics& m = r->metrics;
    const double n = static_cast<double>(tr.t.size());
    m["alpha"] = r->alpha;
    m["beta"] = r->beta;
    m["lambda"] = r->lambda;
    m["alpha_dare"] = r->alpha_dare;
    m["beta_dare"] = r->beta_dare;
    m["missing_fraction"] = n > 0 ? static_cast<double>(tr.lost_samples) / n : kNoSample;
    m["skipped_fraction"] = n > 0 ? static_cast<double>(tr.skipped_updates) / n : kNoSample;
    // The settled gain (end of the longest unbroken run of updates), not the last update's,
    // which may follow a skipped sample; for the steady filter both are α and β/Ts.
    const SettledGain settled = settled_gain(tr);
    m["K1_final"] = settled.K1;
    m["K2_final_times_Ts"] = settled.K2 * r->Ts_s;
    m["K_final_run"] = static_cast<double>(settled.run);
    if (settled.run == 0) {
      for (const char* k : {"K1_final", "K2_final_times_Ts"})
        r->undefined.emplace(k, "no measurement update in this run");
    }
    add_consistency_metrics(r->channels(), r->nees_series(), m, r->undefined);
    m["steps"] = n;
    m["Ts"] = r->Ts_s;
    return std::shared_ptr<RunResult>(std::move(r));
  }

  Expected<Metrics> gain(const ParamValues& v, const Dataset* data) const override {
    if (auto st = params().check(v); !st) return st.err();
    const bool from_data = data && data->rows() >= 2 && param(v, "mode") == kReplay;
    const double Ts = from_data ? data->median_dt() : param(v, "Ts");
    const double Q = param(v, "Q"), R = param(v, "R");
    auto ss = steady_gain_dare(Ts, Q, R);
    if (!ss) return ss.err();
    const double lambda = tracking_index(Ts, Q, R);
    const AlphaBeta ab = alpha_beta(lambda);
    Metrics g;
    g["lambda"] = lambda;
    g["alpha"] = ab.alpha;
    g["beta"] = ab.beta;
    g["alpha_dare"] = ss->alpha;
    g["beta_dare"] = ss->beta;
    g["K1"] = ab.alpha;
    g["K2"] = ab.beta / Ts;
    g["P11_pred_dare"] = ss->P_pred(0, 0);
    g["Ts"] = Ts;
    return g;
  }

 private:
  static std::size_t first_index_at(const std::vector<double>& t, double time_s) {
    std::size_t i = 0;
    while (i < t.size() && !(t[i] >= time_s - 1e-9))
      ++i;
    return i;
  }
  static double mean_square(const std::vector<double>& v) {
    double sum = 0.0;
    std::size_t n = 0;
    for (double x : v)
      if (std::isfinite(x)) sum += x * x, ++n;
    return n ? sum / static_cast<double>(n) : kNoSample;
  }
  static double max_abs(const std::vector<double>& v) {
    double m = 0.0;
    for (double x : v)
      if (std::isfinite(x)) m = std::max(m, std::abs(x));
    return m;
  }
};

}  // namespace

namespace ballbeam {

std::vector<InnovationChannel> BallbeamResult::channels() const {
  InnovationChannel c;
  c.name = "position";
  c.nis = trace.nis;
  c.normalized.assign(trace.nis.size(), kNoSample);
  c.log_det_s.assign(trace.nis.size(), kNoSample);
  for (std::size_t k = 0; k < trace.nis.size(); ++k) {
    if (std::isfinite(trace.nis[k]) && trace.S[k] > 0) {
      c.normalized[k] = trace.innovation[k] / std::sqrt(trace.S[k]);
      c.log_det_s[k] = std::log(trace.S[k]);
    }
  }
  return {c};
}

std::vector<StateSeries> BallbeamResult::states() const {
  const bool truth_x = trace.x_true.size() == trace.t.size();
  const bool truth_v = trace.v_true.size() == trace.t.size();
  return {
      {"x", "x (ball position)", "m", &trace.x_hat, &trace.P11, truth_x ? &trace.x_true : nullptr},
      {"v", "ẋ (ball velocity)", "m/s", &trace.v_hat, &trace.P22,
       truth_v ? &trace.v_true : nullptr}};
}

NeesSeries BallbeamResult::nees_series() const {
  NeesSeries n;
  n.dof = 1.0;  // position only: the trace keeps P11 and P22 but not P12
  n.nees.assign(trace.t.size(), kNoSample);
  for (std::size_t k = 0; k < trace.t.size() && k < trace.x_true.size(); ++k) {
    const double e = trace.x_hat[k] - trace.x_true[k];
    if (std::isfinite(e) && trace.P11[k] > 0) n.nees[k] = e * e / trace.P11[k];
  }
  return n;
}

Dataset BallbeamResult::table() const {
  Dataset d = to_dataset(trace, "ballbeam run");
  const std::pair<const char*, const std::vector<double>*> cols[] = {
      {"x_hat", &trace.x_hat},
      {"v_hat", &trace.v_hat},
      {"P11", &trace.P11},
      {"P22", &trace.P22},
      {"innovation", &trace.innovation},
      {"S", &trace.S},
      {"nis", &trace.nis},
      {"K1", &trace.K1},
      {"K2", &trace.K2},
      {"flagged", &trace.flagged},
      {"theta_c", &trace.theta_c},
      {"V", &trace.V},
      {"x_noise_free", &x_noise_free},
      {"x_detect_on", &x_detect_on},
      {"x_detect_off", &x_detect_off}};
  const std::size_t n = t.size();
  for (const auto& [name, v] : cols) {
    if (v->size() < n) continue;  // the variants run on the loop's grid: cut to this run's
    d.names.emplace_back(name);
    d.columns.emplace_back(v->begin(), v->begin() + static_cast<std::ptrdiff_t>(n));
  }
  return d;
}

}  // namespace ballbeam

void register_scenario_ballbeam(ScenarioRegistry& registry) {
  registry.add("ballbeam", [] { return std::make_unique<BallbeamScenario>(); });
}

}  // namespace kfw
