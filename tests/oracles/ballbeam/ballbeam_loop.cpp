// Random streams (core/random.h; presets/models/README.md, "Random numbers"), all seeded from
// sim.seed, each drawn in time order over the whole run (make_disturbances):
//   channel.position   one normal per sample: the position reading's noise while in contact
//   dropout.position   one uniform per sample: outside a contact loss, u < contact_loss_rate
//                      starts one at that sample (inside one, the uniform is drawn and unused)
//   burst.position     one uniform u per contact loss: it lasts 1 + ⌊ln u / ln(1 − 1/burst)⌋
//                      samples (geometric, mean burst; 1 sample when burst = 1)
//   impulse.position   one uniform u per lost sample: the spike reading −L/2 + L·u along the wire
// The names and draws of a model world's sensor `position` with impulses (issue 30), so that
// presets/ballbeam.json's world draws the same numbers.
#include "oracles/ballbeam/ballbeam_loop.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/random.h"

namespace kfw::ballbeam {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDivergedM = 1e3;  // a ball 1 km from the pivot: the loop has blown up

// ξ = [θ, θ̇, x, ẋ]; ξ̇ = A ξ + B V (seed 003, eq. 11).
using State = std::array<double, 4>;

State derivative(const Plant& pl, const State& s, double V) {
  return {s[1], pl.a1 * s[1] + pl.a2 * s[2] + pl.b1 * V, s[3], pl.a3 * s[0]};
}

State rk4(const Plant& pl, const State& s, double V, double h) {
  auto add = [](const State& a, const State& b, double c) {
    return State{a[0] + c * b[0], a[1] + c * b[1], a[2] + c * b[2], a[3] + c * b[3]};
  };
  const State k1 = derivative(pl, s, V);
  const State k2 = derivative(pl, add(s, k1, h / 2), V);
  const State k3 = derivative(pl, add(s, k2, h / 2), V);
  const State k4 = derivative(pl, add(s, k3, h), V);
  State out;
  for (int i = 0; i < 4; ++i)
    out[i] = s[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  return out;
}

void record_filter(LoopTrace& tr, std::size_t k, const BallTracker::Step& s, bool flagged) {
  tr.flagged[k] = flagged ? 1.0 : 0.0;
  tr.x_hat[k] = s.out.x(kPos);
  tr.v_hat[k] = s.out.x(kVel);
  tr.P11[k] = s.out.P(0, 0);
  tr.P22[k] = s.out.P(1, 1);
  tr.innovation[k] = s.innovation;
  tr.S[k] = s.S;
  tr.nis[k] = s.nis;
  tr.K1[k] = s.K1;
  tr.K2[k] = s.K2;
}

}  // namespace

void LoopTrace::resize(std::size_t n) {
  for (auto* v :
       {&t,       &setpoint, &x_true, &v_true, &theta, &theta_c,    &V, &x_meas, &v_raw, &v_sensor,
        &flagged, &x_hat,    &v_hat,  &P11,    &P22,   &innovation, &S, &nis,    &K1,    &K2})
    v->assign(n, kNaN);
}

void LoopTrace::truncate(std::size_t n) {
  for (auto* v :
       {&t,       &setpoint, &x_true, &v_true, &theta, &theta_c,    &V, &x_meas, &v_raw, &v_sensor,
        &flagged, &x_hat,    &v_hat,  &P11,    &P22,   &innovation, &S, &nis,    &K1,    &K2})
    v->resize(std::min(n, v->size()));
}

std::size_t loop_steps(const LoopParams& p) {
  return static_cast<std::size_t>(std::floor(p.duration_s / p.Ts_s + 1e-9)) + 1;
}

Disturbances make_disturbances(std::size_t n, const LoopParams& p) {
  Disturbances d;
  d.noise_m.resize(n);
  d.lost.assign(n, 0);
  d.spike_m.assign(n, kNaN);
  RandomStream noise(p.seed, "channel.position"), loss(p.seed, "dropout.position");
  RandomStream burst(p.seed, "burst.position"), spike(p.seed, "impulse.position");
  // Geometric number of extra lost samples, P(extra ≥ j) = (1 − 1/burst)^j: mean burst − 1.
  const double log_stay = p.burst > 1 ? std::log(1.0 - 1.0 / p.burst) : 0.0;
  for (std::size_t k = 0; k < n; ++k)
    d.noise_m[k] = p.sigma_pos_m * noise.normal();
  std::size_t lost_until = 0;  // the first sample after the contact loss under way
  for (std::size_t k = 0; k < n; ++k) {
    const bool starts = loss.uniform() < p.contact_loss_rate;
    if (k < lost_until || !starts) continue;
    const double u = burst.uniform();
    const double extra = log_stay < 0.0 ? std::floor(std::log(u) / log_stay) : 0.0;
    lost_until = k + 1 + static_cast<std::size_t>(std::min(extra, static_cast<double>(n)));
    for (std::size_t j = k; j < std::min(n, lost_until); ++j) {
      d.lost[j] = 1;
      // A floating wiper reads anything between the rails: a spike anywhere along the beam.
      const double L = p.sensor.beam_length_m;
      d.spike_m[j] = -0.5 * L + L * spike.uniform();
    }
  }
  return d;
}

LoopTrace run_closed_loop(const LoopParams& p, const BallTracker& tracker, const Disturbances& d,
                          const LoopOptions& opt, const RunControl& control) {
  const std::size_t n = std::min({loop_steps(p), d.noise_m.size(), d.lost.size()});
  LoopTrace tr;
  tr.resize(n);
  const Plant& pl = p.plant;
  const Controller& c = p.ctrl;
  const double Ts = p.Ts_s;
  const int substeps = std::max(1, static_cast<int>(std::ceil(Ts / 1e-3 - 1e-9)));
  const double h = Ts / substeps;
  State s{0.0, 0.0, p.x0_m, 0.0};
  double integral = 0.0;  // ∫(θc − θ) dt
  double uc_prev = 0.0;
  Gaussian<2> out;
  for (std::size_t k = 0; k < n; ++k) {
    tr.t[k] = static_cast<double>(k) * Ts;
    tr.setpoint[k] = tr.t[k] >= p.step_time_s - 1e-9 ? p.setpoint_m : 0.0;
  }
  for (std::size_t k = 0; k < n; ++k) {
    if ((k & 1023) == 0 && control.cancelled()) break;
    const double tk = tr.t[k];
    if (opt.falls && std::abs(s[2]) > p.sensor.half_length_m()) {
      // Off the end of the beam: the ball has fallen, nothing more to control or track.
      tr.fell = true;
      tr.left_beam_at_s = tk;
      tr.truncate(k);
      break;
    }
    const double xc = tr.setpoint[k];
    const bool lost = opt.impulsive && d.lost[k];
    const double reading = lost ? d.spike_m[k] : s[2] + (opt.impulsive ? d.noise_m[k] : 0.0);
    const double v_raw = p.sensor.volts(reading);
    const double v_circuit = lost ? 0.0 : v_raw;
    const bool flagged = opt.detection && v_circuit == 0.0;  // the circuit's 0 V ⇒ missing
    // The tracker starts on the first usable reading (else at the known rest position x0).
    const Gaussian<2> prior =
        k == 0 ? tracker.initial(flagged ? p.x0_m : reading) : tracker.predict(out, uc_prev);
    const BallTracker::Step st = tracker.update(prior, reading, flagged);
    out = st.out;
    const double theta_c = c.Kx * (xc - out.x(kPos)) - c.Kv * out.x(kVel);
    const double e = theta_c - s[0];
    const double V_free = c.Kp * e + c.KI * (integral + e * Ts) - c.KD * s[1];
    const double V = std::clamp(V_free, -p.V_max, p.V_max);
    // Anti-windup: integrate only while the amplifier is not saturated.
    if (V == V_free) integral += e * Ts;

    tr.x_true[k] = s[2];
    tr.v_true[k] = s[3];
    tr.theta[k] = s[0];
    tr.theta_c[k] = theta_c;
    tr.V[k] = V;
    tr.x_meas[k] = reading;
    tr.v_raw[k] = v_raw;
    tr.v_sensor[k] = v_circuit;
    record_filter(tr, k, st, flagged);
    tr.lost_samples += lost ? 1 : 0;
    tr.skipped_updates += st.updated ? 0 : 1;

    uc_prev = pl.a3 * s[0];  // u^c_k = a3 θ_k from the beam potentiometer
    for (int i = 0; i < substeps; ++i) {
      s = rk4(pl, s, V, h);
      if (std::abs(s[0]) > p.theta_max_rad) {  // on a stop: held there until driven back
        s[0] = std::copysign(p.theta_max_rad, s[0]);
        if (s[1] * s[0] > 0.0) s[1] = 0.0;
      }
    }
    const bool finite = std::all_of(s.begin(), s.end(), [](double v) { return std::isfinite(v); });
    if (!finite || std::abs(s[2]) > kDivergedM || !std::isfinite(V)) {
      tr.diverged = true;
      tr.diverged_at_s = tk + Ts;
      break;
    }
  }
  if (!tr.fell) tr.left_beam_at_s = left_beam_at(tr.t, tr.x_true, p.sensor.half_length_m());
  return tr;
}

double left_beam_at(const std::vector<double>& t, const std::vector<double>& x_m,
                    double half_length_m) {
  const std::size_t n = std::min(t.size(), x_m.size());
  for (std::size_t k = 0; k < n; ++k) {
    if (std::isfinite(x_m[k]) && std::abs(x_m[k]) > half_length_m) return t[k];
  }
  return kNaN;
}

SettledGain settled_gain(const LoopTrace& tr) {
  SettledGain best;
  std::size_t run = 0;
  const std::size_t n = std::min(tr.K1.size(), tr.K2.size());
  for (std::size_t k = 0; k < n; ++k) {
    // K1 is NaN exactly where the update was skipped (flagged or no reading).
    if (!std::isfinite(tr.K1[k])) {
      run = 0;
      continue;
    }
    ++run;
    if (run >= best.run) best = {tr.K1[k], tr.K2[k], run};
  }
  return best;
}

LoopTrace replay(const std::vector<double>& t, const std::vector<double>& x_meas,
                 const std::vector<double>* v_sensor, const std::vector<double>* theta,
                 const BallTracker& tracker, bool detection, double a3, const RunControl& control) {
  const std::size_t n = std::min(t.size(), x_meas.size());
  LoopTrace tr;
  tr.resize(n);
  Gaussian<2> out;
  double uc_prev = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if ((k & 1023) == 0 && control.cancelled()) break;
    const double y = x_meas[k];
    const bool zero_volts = v_sensor && (*v_sensor)[k] == 0.0;
    const bool lost = zero_volts || !std::isfinite(y);
    const bool flagged = !std::isfinite(y) || (detection && zero_volts);
    const Gaussian<2> prior =
        k == 0 ? tracker.initial(flagged ? 0.0 : y) : tracker.predict(out, uc_prev);
    const BallTracker::Step st = tracker.update(prior, y, flagged);
    out = st.out;
    tr.t[k] = t[k];
    tr.x_meas[k] = y;
    if (v_sensor) tr.v_sensor[k] = (*v_sensor)[k];
    if (theta) tr.theta[k] = (*theta)[k];
    record_filter(tr, k, st, flagged);
    tr.lost_samples += lost ? 1 : 0;
    tr.skipped_updates += st.updated ? 0 : 1;
    const double th = theta ? (*theta)[k] : 0.0;
    uc_prev = std::isfinite(th) ? a3 * th : 0.0;
  }
  return tr;
}

Dataset to_dataset(const LoopTrace& tr, const std::string& source) {
  Dataset d;
  d.source = source;
  const std::pair<const char*, const std::vector<double>*> cols[] = {
      {"t", &tr.t},          {"x_meas", &tr.x_meas}, {"v_sensor", &tr.v_sensor},
      {"v_raw", &tr.v_raw},  {"theta", &tr.theta},   {"setpoint", &tr.setpoint},
      {"truth", &tr.x_true}, {"v_truth", &tr.v_true}};
  for (const auto& [name, v] : cols) {
    d.names.emplace_back(name);
    d.columns.push_back(*v);
  }
  return d;
}

}  // namespace kfw::ballbeam
