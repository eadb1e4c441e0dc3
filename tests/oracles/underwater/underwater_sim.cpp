// Random streams (core/random.h; presets/models/README.md, "Random numbers"), all seeded from
// sim.seed, one per noise source; each draws in time order:
//   noise.n_u … noise.n_r   one normal per motion step (0.01 s) each: the velocity noise on u, v,
//                           w, p, q, r (Table 1), drawn from the first step on
//   clock.SENSOR            one normal per tick: that sensor's clock jitter n_t (Table 2), SENSOR
//                           dvl, ahrs, range1..range4, depth; clock.sync for the shared clock
//   channel.SENSOR          one normal per component per sample, in column order: dvl (u, v, w),
//                           ahrs (φ, θ, ψ, p, q, r), range1..range4, depth (eq. 1–3)
//   noise.n_c               one normal per t_gap window: the correlated range noise (Table 7)
//   dropout.rangeN          one uniform per sample of range N: u < range_dropout loses it
//   outliers.range          per outlier i = 0..N−1: one uniform u picks the sample (below), one
//                           uniform v its sign (v < ½: −σ_o, else +σ_o)
// The outliers (Table 8) are drawn without replacement from the M range samples kept, listed in
// row order and beacon order inside a row: the i-th swaps sample i with sample
// j = i + ⌊u (M − i)⌋ (clamped to M − 1) and offsets the sample now at i.
#include "oracles/underwater/underwater_sim.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/random.h"

namespace kfw::underwater {

namespace {

double wrap_pi(double a) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  a = std::fmod(a + std::numbers::pi, kTwoPi);
  if (a < 0.0) a += kTwoPi;
  return a - std::numbers::pi;
}

double snap(double t) {
  return std::round(t / kTimeGrid_s) * kTimeGrid_s;
}

// Sensor times t_{s,i} = t_{s,i-1} + Δt + n_t (seed 004, Table 2), from 0 to the end of the run.
// An interval never shrinks below Δt/10, so time stays increasing whatever σ_t is.
std::vector<double> clock(double dt_s, double sigma_t_s, double duration_s, RandomStream jitter) {
  std::vector<double> t;
  t.reserve(static_cast<std::size_t>(duration_s / dt_s) + 2);
  double ts = 0.0;
  while (ts <= duration_s + 1e-9) {
    t.push_back(snap(ts));
    ts += std::max(dt_s + sigma_t_s * jitter.normal(), 0.1 * dt_s);
  }
  return t;
}

}  // namespace

const char* sensor_name(int s) {
  static const char* const kNames[kSensorCount] = {"dvl",    "ahrs",   "range1", "range2",
                                                   "range3", "range4", "depth"};
  return s >= 0 && s < kSensorCount ? kNames[s] : "?";
}

Mat<3> rotation(double phi, double theta, double psi) {
  const double cf = std::cos(phi), sf = std::sin(phi);
  const double ct = std::cos(theta), st = std::sin(theta);
  const double cp = std::cos(psi), sp = std::sin(psi);
  Mat<3> R;
  R << cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf,  //
      sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf,   //
      -st, ct * sf, ct * cf;
  return R;
}

Vec<6> motion_model(const Vec<6>& pose, const Vec<6>& velocity, double dt_s) {
  // Euler-angle rates from body rates (Fossen): φ̇ = p + (q sφ + r cφ) tθ, θ̇ = q cφ − r sφ,
  // ψ̇ = (q sφ + r cφ)/cθ; the position moves with the attitude at mid-step.
  if (pose(3) == 0.0 && pose(4) == 0.0 && velocity(3) == 0.0 && velocity(4) == 0.0) {
    // Level motion (the seed 004 runs): only the yaw turns, the same formulas with φ = θ = 0.
    const double psi_mid = pose(5) + 0.5 * dt_s * velocity(5);
    const double c = std::cos(psi_mid), s = std::sin(psi_mid);
    Vec<6> out = pose;
    out(0) += dt_s * (c * velocity(0) - s * velocity(1));
    out(1) += dt_s * (s * velocity(0) + c * velocity(1));
    out(2) += dt_s * velocity(2);
    out(5) += dt_s * velocity(5);
    return out;
  }
  auto euler_rate = [&](const Vec<3>& att) {
    const double sf = std::sin(att(0)), cf = std::cos(att(0));
    const double ct = std::cos(att(1)), tt = std::tan(att(1));
    const double p = velocity(3), q = velocity(4), r = velocity(5);
    return Vec<3>(p + (q * sf + r * cf) * tt, q * cf - r * sf, (q * sf + r * cf) / ct);
  };
  const Vec<3> att0 = pose.tail<3>();
  const Vec<3> att_mid = att0 + 0.5 * dt_s * euler_rate(att0);
  const Vec<3> att1 = att0 + dt_s * euler_rate(att_mid);
  Vec<6> out;
  out.head<3>() =
      pose.head<3>() + dt_s * rotation(att_mid(0), att_mid(1), att_mid(2)) * velocity.head<3>();
  out.tail<3>() = att1;
  return out;
}

namespace {

// Sensor clocks (Table 2): one shared clock, or one per sensor with the Table 3 periods, each with
// its own jitter stream. The (time, sensor) events in time order, sensors in enum order at a time.
std::vector<std::pair<double, int>> sensor_events(const SimParams& p) {
  std::vector<std::pair<double, int>> events;
  if (p.synchronous) {
    for (double t : clock(p.dt_sync_s, p.sigma_t_s, p.duration_s, {p.seed, "clock.sync"})) {
      for (int s = 0; s < kSensorCount; ++s)
        events.emplace_back(t, s);
    }
  } else {
    for (int s = 0; s < kSensorCount; ++s) {
      RandomStream jitter(p.seed, std::string("clock.") + sensor_name(s));
      for (double t : clock(p.period_s[static_cast<std::size_t>(s)], p.sigma_t_s, p.duration_s,
                            std::move(jitter))) {
        events.emplace_back(t, s);
      }
    }
  }
  std::sort(events.begin(), events.end());
  return events;
}

// The index i + ⌊u (M − i)⌋ of a draw without replacement from the M − i samples left (u from
// RandomStream::uniform, in (0, 1]; clamped, so u = 1 gives M − 1).
std::size_t pick(std::size_t i, std::size_t m, double u) {
  const double j = static_cast<double>(i) + std::floor(u * static_cast<double>(m - i));
  return std::min(static_cast<std::size_t>(j), m - 1);
}

// The dataset's columns, every cell empty (NaN).
Dataset empty_dataset(const SimParams& p, std::size_t n) {
  Dataset d;
  d.source = "simulated underwater, seed " + std::to_string(p.seed);
  const char* names[] = {"t",        "dvl_u",   "dvl_v",  "dvl_w",  "ahrs_phi", "ahrs_theta",
                         "ahrs_psi", "ahrs_p",  "ahrs_q", "ahrs_r", "range1",   "range2",
                         "range3",   "range4",  "depth",  "x_true", "y_true",   "z_true",
                         "psi_true", "x_cmd",   "y_cmd",  "z_cmd",  "outlier1", "outlier2",
                         "outlier3", "outlier4"};
  for (const char* name : names)
    d.add(name, n);
  return d;
}

std::vector<double>& column(Dataset& d, const std::string& name) {
  return d.columns[static_cast<std::size_t>(d.index(name))];
}

// Motion (Table 1), generated forward in time alongside the rows: u(t_j) = u_cmd + n_u,
// x(t_{j+1}) = motion_model(u(t_j), x(t_j)); the command alone gives the command trajectory.
// A row's pose is propagated from the motion sample t_j <= t (Tables 5–6, lines 5–6). Fills the
// time, truth and command columns; returns each row's pose and velocity.
std::pair<std::vector<Vec<6>>, std::vector<Vec<6>>> simulate_motion(
    const SimParams& p, const std::vector<double>& row_t, Dataset& d) {
  const std::size_t n = row_t.size();
  std::vector<double>* truth[4] = {&column(d, "x_true"), &column(d, "y_true"), &column(d, "z_true"),
                                   &column(d, "psi_true")};
  std::vector<double>* cmd[3] = {&column(d, "x_cmd"), &column(d, "y_cmd"), &column(d, "z_cmd")};
  std::vector<Vec<6>> row_pose(n), row_vel(n);
  Vec<6> pose = Vec<6>::Zero(), pose_cmd = Vec<6>::Zero(), vel;
  std::size_t j = 0;
  std::vector<RandomStream> motion;
  for (const char* c : {"u", "v", "w", "p", "q", "r"})
    motion.emplace_back(p.seed, std::string("noise.n_") + c);
  auto draw_velocity = [&] {
    for (int i = 0; i < 6; ++i)
      vel(i) = p.command(i) + p.motion_sigma(i) * motion[static_cast<std::size_t>(i)].normal();
  };
  draw_velocity();
  for (std::size_t k = 0; k < n; ++k) {
    // A row within 1 ns of a motion step is at that step (as a model file's world steps its grid).
    const auto jk =
        static_cast<std::size_t>(std::max(0.0, std::floor((row_t[k] + 1e-9) / kMotionDt_s)));
    while (j < jk) {
      pose = motion_model(pose, vel, kMotionDt_s);
      pose_cmd = motion_model(pose_cmd, p.command, kMotionDt_s);
      draw_velocity();
      ++j;
    }
    const double dt = row_t[k] - static_cast<double>(j) * kMotionDt_s;
    column(d, "t")[k] = row_t[k];
    row_pose[k] = motion_model(pose, vel, dt);
    row_vel[k] = vel;
    const Vec<6> c = motion_model(pose_cmd, p.command, dt);
    for (int i = 0; i < 3; ++i)
      (*truth[i])[k] = row_pose[k](i);
    (*truth[3])[k] = row_pose[k](5);
    for (int i = 0; i < 3; ++i)
      (*cmd[i])[k] = c(i);
  }
  return {std::move(row_pose), std::move(row_vel)};
}

// Outliers (Table 8): N of the (row, beacon) range samples, drawn without replacement, get ±σ_o.
void add_outliers(const SimParams& p, std::vector<std::pair<std::size_t, int>> range_samples,
                  Dataset& d) {
  const std::size_t m = range_samples.size();
  const std::size_t n_out = std::min(m, static_cast<std::size_t>(std::max(0, p.outliers)));
  RandomStream draws(p.seed, "outliers.range");
  for (std::size_t i = 0; i < n_out; ++i) {
    std::swap(range_samples[i], range_samples[pick(i, m, draws.uniform())]);
    const auto [k, b] = range_samples[i];
    const double offset = draws.uniform() < 0.5 ? -p.outlier_m : p.outlier_m;
    const std::string beacon = std::to_string(b + 1);
    column(d, "range" + beacon)[k] += offset;
    column(d, "outlier" + beacon)[k] = offset;
  }
}

}  // namespace

Dataset simulate(const SimParams& p) {
  const std::vector<std::pair<double, int>> events = sensor_events(p);
  std::vector<double> row_t;
  std::vector<int> row_of_event(events.size());
  for (std::size_t e = 0; e < events.size(); ++e) {
    if (row_t.empty() || events[e].first != row_t.back()) row_t.push_back(events[e].first);
    row_of_event[e] = static_cast<int>(row_t.size()) - 1;
  }
  Dataset d = empty_dataset(p, row_t.size());
  const auto [row_pose, row_vel] = simulate_motion(p, row_t, d);
  std::vector<double>* dvl[3] = {&column(d, "dvl_u"), &column(d, "dvl_v"), &column(d, "dvl_w")};
  std::vector<double>* ahrs[6] = {&column(d, "ahrs_phi"), &column(d, "ahrs_theta"),
                                  &column(d, "ahrs_psi"), &column(d, "ahrs_p"),
                                  &column(d, "ahrs_q"),   &column(d, "ahrs_r")};
  std::vector<double>* range[kBeacons] = {&column(d, "range1"), &column(d, "range2"),
                                          &column(d, "range3"), &column(d, "range4")};
  std::vector<double>* outlier[kBeacons] = {&column(d, "outlier1"), &column(d, "outlier2"),
                                            &column(d, "outlier3"), &column(d, "outlier4")};
  auto& depth = column(d, "depth");
  const auto& t = column(d, "t");

  // Correlated range noise n_c (Table 7): one draw per t_gap window, shared by all ranges.
  const auto windows = static_cast<std::size_t>(std::floor(p.duration_s / p.t_gap_s)) + 2;
  std::vector<double> n_c(windows);
  RandomStream corr(p.seed, "noise.n_c");
  for (double& v : n_c)
    v = p.sigma_corr_m * corr.normal();

  // Measurements at each sensor time (eq. 1–3 plus n_c).
  std::vector<RandomStream> channel, dropout;
  for (int s = 0; s < kSensorCount; ++s) {
    channel.emplace_back(p.seed, std::string("channel.") + sensor_name(s));
    dropout.emplace_back(p.seed, std::string("dropout.") + sensor_name(s));
  }
  std::vector<std::pair<std::size_t, int>> range_samples;  // (row, beacon) for Table 8
  for (std::size_t e = 0; e < events.size(); ++e) {
    const auto k = static_cast<std::size_t>(row_of_event[e]);
    const int s = events[e].second;
    const Vec<6>& x = row_pose[k];
    const Vec<6>& u = row_vel[k];
    RandomStream& sensor = channel[static_cast<std::size_t>(s)];
    if (s == kDvl) {
      for (int i = 0; i < 3; ++i)
        (*dvl[i])[k] = u(i) + p.velocity_sigma(i) * sensor.normal();
    } else if (s == kAhrs) {
      for (int i = 0; i < 3; ++i) {
        const double a = x(3 + i) + p.attitude_sigma_rad * sensor.normal();
        (*ahrs[i])[k] = i == 2 ? wrap_pi(a) : a;
      }
      for (int i = 3; i < 6; ++i)
        (*ahrs[i])[k] = u(i) + p.velocity_sigma(i) * sensor.normal();
    } else if (s == kDepth) {
      depth[k] = x(2) + p.sigma_depth_m * sensor.normal();
    } else {
      const int b = s - kRange1;
      const double noise = p.sigma_range_m * sensor.normal();
      if (dropout[static_cast<std::size_t>(s)].uniform() < p.range_dropout) continue;
      const auto w = std::min(static_cast<std::size_t>(t[k] / p.t_gap_s), windows - 1);
      const auto bi = static_cast<std::size_t>(b);
      (*range[bi])[k] = (beacons()[bi] - x.head<3>()).norm() + noise + n_c[w];
      (*outlier[bi])[k] = 0.0;
      range_samples.emplace_back(k, b);
    }
  }

  add_outliers(p, std::move(range_samples), d);
  return d;
}

}  // namespace kfw::underwater
