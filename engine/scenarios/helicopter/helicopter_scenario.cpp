// The `helicopter` scenario (seed 000; docs/reproductions.md): parameter table, schema, simulator
// and runner.
#include <cmath>
#include <memory>

#include "core/scenario.h"
#include "core/statistics.h"
#include "filter/consistency.h"
#include "scenarios/helicopter/helicopter_model.h"
#include "scenarios/helicopter/helicopter_sim.h"
#include "scenarios/helicopter/indirect_kf.h"

namespace kfw {

namespace {

ParamTable make_table() {
  const std::string F = "Filter", S = "Simulator";
  return ParamTable({
      {"Q", "Q = N_ω, gyro noise variance", "(deg/s)²", 1e-6, 1e6, 67.24, Scale::kLog, F,
       "Gyro white-noise variance N_ω driving the angle error (Kim et al., eq. 7)."},
      {"R", "R = N_θ, angle noise variance", "deg²", 1e-6, 1e6, 1.96, Scale::kLog, F,
       "Absolute angle sensor noise variance N_θ (Kim et al., eq. 8)."},
      {"m", "m, gyro samples per angle update", "", 1, 200, 1, Scale::kInteger, F,
       "The angle sensor updates every m-th gyro sample (Kim et al., eq. 10)."},
      {"gamma", "γ, bias cutoff ratio", "", 0.0, 0.1, 0.0, Scale::kLinear, F,
       "b_k = (1-γ) b_{k-1} + γ ω_m (Kim et al., eq. 12); 0 = constant bias.", 4},
      {"P0_theta", "P0 angle variance", "deg²", 1e-6, 1e6, 100.0, Scale::kLog, F,
       "Initial P11 (Kim et al.: 100 deg²)."},
      {"P0_bias", "P0 bias variance", "(deg/s)²", 1e-6, 1e6, 4.0, Scale::kLog, F,
       "Initial P22 (Kim et al.: 4 (deg/s)²)."},
      {"window", "consistency window", "updates", 1, 1000, 50, Scale::kInteger, "Consistency",
       "Moving-average window of NIS and NEES, in angle updates (the χ² bounds follow it)."},
      {"sim.seed", "seed", "", 0, 1e6, 1, Scale::kInteger, S, "Random seed of the simulator."},
      {"sim.duration", "duration", "s", 1, 3600, 120, Scale::kLinear, S, "Length of the run.", 0},
      {"sim.Ts", "gyro period Ts", "s", 0.001, 0.1, 0.02, Scale::kLinear, S,
       "Sample period of gyro and angle sensor (Kim et al.: 20 ms).", 3},
      {"sim.amplitude", "attitude amplitude", "deg", 0, 45, 10, Scale::kLinear, S,
       "Size of the hover sway.", 1},
      {"sim.sigma_gyro", "σ gyro", "deg/s", 0, 20, 8.2, Scale::kLinear, S,
       "Gyro white noise per sample (Kim et al., engine on: 7.72–8.71 deg/s).", 2},
      {"sim.sigma_angle", "σ angle", "deg", 0, 10, 1.4, Scale::kLinear, S,
       "Angle sensor noise (Kim et al., engine on: 1.37–1.45 deg).", 2},
      {"sim.bias0", "initial gyro bias", "deg/s", -10, 10, 1.5, Scale::kLinear, S, "", 2},
      {"sim.bias_walk", "bias random walk", "(deg/s)/√s", 0, 1, 0.05, Scale::kLinear, S,
       "Bias drift density: the slowly varying bias that γ tracks.", 3},
      {"sim.angle_dropout", "angle dropout", "", 0, 0.99, 0.0, Scale::kLinear, S,
       "Probability that an angle sample is missing.", 2},
  });
}

// The helicopter metrics beyond the shared vocabulary (rmse is the angle θ, rmse.bias the bias).
std::vector<MetricSpec> make_metric_specs() {
  using G = MetricGroup;
  using D = Direction;
  return {
      {"rmse_sensor", "RMSE of the angle sensor alone", "deg",
       "RMSE of the raw angle readings against truth: what the filter has to beat", G::kAccuracy,
       D::kLower},
      {"k1_final", "k1 at the last update", "", "angle gain of the last angle update", G::kGains,
       D::kNone},
      {"k1_steady", "k1 (DARE)", "",
       "steady-state angle gain of the m-step model from the DARE, at the data's Ts", G::kGains,
       D::kNone},
      {"k1_closed_form", "k1 (closed form)", "",
       "steady-state angle gain k1(β) of the constant-bias model (Kim et al., eq. 11)", G::kGains,
       D::kNone},
      {"beta", "β, operating point", "",
       "β = m Ts² N_ω / N_θ, the one number k1 depends on (Kim et al., eq. 11)", G::kGains,
       D::kNone},
  };
}

class HelicopterScenario final : public Scenario {
 public:
  std::string primary_state() const override { return "theta"; }
  std::vector<MetricSpec> metric_specs() const override {
    static const std::vector<MetricSpec> specs = make_metric_specs();
    return specs;
  }
  std::string name() const override { return "helicopter"; }
  std::string title() const override {
    return "Helicopter attitude: indirect KF, gyro + angle sensor (Kim et al.)";
  }
  const ParamTable& params() const override {
    static const ParamTable table = make_table();
    return table;
  }
  std::vector<ColumnSpec> columns() const override {
    return {{"t", "s", "time", true},
            {"gyro", "deg/s", "rate gyro", true},
            {"angle", "deg", "absolute angle sensor; empty = no sample", true},
            {"truth", "deg", "true angle; empty where unknown", false}};
  }

  Expected<Dataset> simulate(const ParamValues& v) const override {
    if (auto st = params().check(v); !st) return st.err();
    helicopter::SimParams s;
    s.seed = static_cast<std::uint64_t>(param(v, "sim.seed"));
    s.duration_s = param(v, "sim.duration");
    s.Ts_s = param(v, "sim.Ts");
    s.amplitude_deg = param(v, "sim.amplitude");
    s.sigma_gyro = param(v, "sim.sigma_gyro");
    s.sigma_angle = param(v, "sim.sigma_angle");
    s.bias0 = param(v, "sim.bias0");
    s.bias_walk = param(v, "sim.bias_walk");
    s.angle_dropout = param(v, "sim.angle_dropout");
    s.x0_from_prior = x0_from_prior_;
    s.P0_theta = param(v, "P0_theta");
    s.P0_bias = param(v, "P0_bias");
    return helicopter::simulate(s);
  }

  // θ(0) ~ N(0, P0_theta), b(0) ~ N(0, P0_bias), and the filter starts from that prior mean (0, 0)
  // instead of the first angle sample.
  std::shared_ptr<const Scenario> with_x0_from_prior() const override {
    auto s = std::make_shared<HelicopterScenario>();
    s->x0_from_prior_ = true;
    return s;
  }

  Expected<std::shared_ptr<RunResult>> run_impl(const Dataset& d, const ParamValues& v,
                                                const RunControl& control) const override {
    if (auto st = params().check(v); !st) return st.err();
    if (auto st = require_columns(d, columns()); !st) return st.err();
    if (d.rows() < 2) return Error{d.source + ": need at least two rows"};
    helicopter::FilterParams fp;
    fp.N_omega = param(v, "Q");
    fp.N_theta = param(v, "R");
    fp.m = static_cast<int>(param(v, "m"));
    fp.gamma = param(v, "gamma");
    fp.P0_theta = param(v, "P0_theta");
    fp.P0_bias = param(v, "P0_bias");
    fp.prior_mean_zero = x0_from_prior_;
    auto r = std::make_shared<helicopter::HelicopterResult>(
        helicopter::run_indirect_kf(d.col("t"), d.col("gyro"), d.col("angle"), fp, control));
    r->truth = d.has("truth") ? d.col("truth") : std::vector<double>(d.rows(), kNoSample);

    r->Ts_s = d.median_dt();
    r->beta = helicopter::beta(fp.m, r->Ts_s, fp.N_omega, fp.N_theta);
    r->k1_closed = helicopter::k1_closed_form(r->beta);
    r->p11_over_R_steady = helicopter::p11_over_R(r->beta);
    auto ss = helicopter::steady_gain_dare(fp.m, r->Ts_s, fp.gamma, fp.N_omega, fp.N_theta);
    r->k1_steady = ss ? ss->k1 : kNoSample;
    if (!ss) {
      r->warnings.push_back("steady-state gain: " + ss.error());
      r->undefined.emplace("k1_steady", "the DARE failed: " + ss.error());
    }

    Metrics& m = r->metrics;
    m["rmse_sensor"] = rmse_finite(r->angle, r->truth);
    if (count_finite(r->truth) == 0)
      r->undefined.emplace("rmse_sensor", "no truth column ('truth') in the data");
    m["k1_final"] = last_finite(r->k1);
    if (r->updates == 0) r->undefined.emplace("k1_final", "the angle sensor never updated");
    m["k1_steady"] = r->k1_steady;
    m["k1_closed_form"] = r->k1_closed;
    m["beta"] = r->beta;
    // Whiteness of the normalised innovations y/√S at the angle sensor's own rate, and the
    // moving-average NIS, for the plots; the metrics come from add_consistency_metrics.
    r->channel_cache = r->channels();
    const auto& channels = r->channel_cache;
    {
      // The channel's normalised innovations; its whiteness metric is this same test.
      r->whiteness = ljung_box(channels.front().normalized, 20);
      if (std::isfinite(r->whiteness.p_value)) m["whiteness_p.angle"] = r->whiteness.p_value;
      r->nis_window = static_cast<std::size_t>(param(v, "window"));
      r->nis_avg = moving_average_finite(r->nis, r->nis_window);
    }
    if (d.has("bias_truth")) r->bias_truth = d.col("bias_truth");
    // NEES of the angle (truth holds θ only; with the simulator's bias truth, of [θ, b]). With
    // γ > 0 the bias has no process noise: P22 decays as (1 − γ)^2k and P turns singular in
    // double precision, where [θ, b]'s NEES is undefined; the run then reports θ's (1 dof).
    {
      std::vector<double> nees(r->steps(), kNoSample);
      const std::vector<double>* bt = r->bias_truth.empty() ? nullptr : &r->bias_truth;
      bool joint = bt != nullptr;
      for (std::size_t k = 0; k < r->steps(); ++k) {
        const double e = r->theta[k] - r->truth[k];
        if (!std::isfinite(e)) continue;
        nees[k] = e * e / r->P11[k];
        if (joint && std::isfinite((*bt)[k])) {
          // e^T P^{-1} e with the 2×2 inverse written out.
          const double eb = r->bias[k] - (*bt)[k];
          const double a = r->P11[k], b = r->P12[k], c = r->P22[k], det = a * c - b * b;
          const double q = (c * e * e - 2.0 * b * e * eb + a * eb * eb) / det;
          if (det > 1e-12 * a * c && std::isfinite(q)) {
            nees[k] = q;
          } else {
            joint = false;
            for (std::size_t j = 0; j <= k; ++j) {
              const double ej = r->theta[j] - r->truth[j];
              nees[j] = std::isfinite(ej) ? ej * ej / r->P11[j] : kNoSample;
            }
          }
        }
      }
      r->nees_dof = joint ? 2.0 : 1.0;
      r->nees_avg = moving_average_finite(nees, r->nis_window);
      r->nees = std::move(nees);
    }
    add_consistency_metrics(channels, r->nees_series(), m, r->undefined);
    return std::shared_ptr<RunResult>(std::move(r));
  }

  Expected<Metrics> gain(const ParamValues& v, const Dataset* data) const override {
    if (auto st = params().check(v); !st) return st.err();
    const int m = static_cast<int>(param(v, "m"));
    const double Ts = data && data->rows() >= 2 ? data->median_dt() : param(v, "sim.Ts");
    return gain_at(v, m, Ts);
  }

  // N_ω and N_θ are the white-noise variances of the gyro and the angle sensor (seed 000, eq. 3):
  // `kfw-cli noise` reads them from the high-frequency part of each column's PSD.
  std::vector<NoiseLink> noise_links() const override {
    return {noise_variance_link("gyro", "Q"), noise_variance_link("angle", "R")};
  }

  static Expected<Metrics> gain_at(const ParamValues& v, int m, double Ts) {
    const double Nw = param(v, "Q"), Nt = param(v, "R"), gamma = param(v, "gamma");
    Metrics g;
    g["beta"] = helicopter::beta(m, Ts, Nw, Nt);
    g["k1"] = helicopter::k1_closed_form(g["beta"]);
    g["p11_over_R"] = helicopter::p11_over_R(g["beta"]);
    auto ss = helicopter::steady_gain_dare(m, Ts, gamma, Nw, Nt);
    if (!ss) return ss.err();
    g["k1_dare"] = ss->k1;
    g["k2_dare"] = ss->k2;
    g["p11_over_R_dare"] = ss->p11_pred / Nt;
    g["Ts"] = Ts;
    g["m"] = m;
    g["gamma"] = gamma;
    return g;
  }

 private:
  bool x0_from_prior_ = false;  // preset sim.x0_from_prior (with_x0_from_prior)
};

}  // namespace

void register_scenario_helicopter(ScenarioRegistry& registry) {
  registry.add("helicopter", [] { return std::make_unique<HelicopterScenario>(); });
}

}  // namespace kfw
