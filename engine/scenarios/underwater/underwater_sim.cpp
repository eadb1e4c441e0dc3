#include "scenarios/underwater/underwater_sim.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

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

// One independent random stream: its own engine and its own distributions. A
// std::normal_distribution caches the second value of each pair it generates, so sharing one
// across engines would hand a draw of one stream to the next caller of another.
class Stream {
 public:
  explicit Stream(std::uint64_t seed) : rng_(seed) {}
  double gauss() { return normal_(rng_); }            // N(0, 1)
  double uniform() { return uniform_(rng_); }         // U[0, 1)
  std::size_t pick(std::size_t lo, std::size_t hi) {  // uniform in [lo, hi]
    return std::uniform_int_distribution<std::size_t>(lo, hi)(rng_);
  }

 private:
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

// Sensor times t_{s,i} = t_{s,i-1} + Δt + n_t (seed 004, Table 2), from 0 to the end of the run.
// An interval never shrinks below Δt/10, so time stays increasing whatever σ_t is.
std::vector<double> clock(double dt_s, double sigma_t_s, double duration_s, Stream& jitter_stream) {
  std::vector<double> t;
  t.reserve(static_cast<std::size_t>(duration_s / dt_s) + 2);
  double ts = 0.0;
  while (ts <= duration_s + 1e-9) {
    t.push_back(snap(ts));
    const double jitter = sigma_t_s > 0.0 ? sigma_t_s * jitter_stream.gauss() : 0.0;
    ts += std::max(dt_s + jitter, 0.1 * dt_s);
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

Dataset simulate(const SimParams& p) {
  // Independent streams, so that changing one uncertainty leaves the others' draws unchanged.
  Stream motion(p.seed * 7919 + 1), clocks(p.seed * 7919 + 2), sensor(p.seed * 7919 + 3),
      corr(p.seed * 7919 + 4), outlier_draws(p.seed * 7919 + 5), drop(p.seed * 7919 + 6);

  // Sensor clocks (Table 2): one shared clock, or one per sensor with the Table 3 periods.
  std::vector<std::pair<double, int>> events;  // (time, sensor)
  if (p.synchronous) {
    for (double t : clock(p.dt_sync_s, p.sigma_t_s, p.duration_s, clocks)) {
      for (int s = 0; s < kSensorCount; ++s)
        events.emplace_back(t, s);
    }
  } else {
    for (int s = 0; s < kSensorCount; ++s) {
      for (double t :
           clock(p.period_s[static_cast<std::size_t>(s)], p.sigma_t_s, p.duration_s, clocks)) {
        events.emplace_back(t, s);
      }
    }
  }
  std::sort(events.begin(), events.end());
  std::vector<double> row_t;
  std::vector<int> row_of_event(events.size());
  for (std::size_t e = 0; e < events.size(); ++e) {
    if (row_t.empty() || events[e].first != row_t.back()) row_t.push_back(events[e].first);
    row_of_event[e] = static_cast<int>(row_t.size()) - 1;
  }
  const std::size_t n = row_t.size();

  Dataset d;
  d.source = "simulated underwater, seed " + std::to_string(p.seed);
  const char* names[] = {"t",        "dvl_u",   "dvl_v",  "dvl_w",  "ahrs_phi", "ahrs_theta",
                         "ahrs_psi", "ahrs_p",  "ahrs_q", "ahrs_r", "range1",   "range2",
                         "range3",   "range4",  "depth",  "x_true", "y_true",   "z_true",
                         "psi_true", "x_cmd",   "y_cmd",  "z_cmd",  "outlier1", "outlier2",
                         "outlier3", "outlier4"};
  for (const char* name : names)
    d.add(name, n);
  auto col = [&](const char* name) -> std::vector<double>& {
    return d.columns[static_cast<std::size_t>(d.index(name))];
  };
  auto& t = col("t");
  std::vector<double>* dvl[3] = {&col("dvl_u"), &col("dvl_v"), &col("dvl_w")};
  std::vector<double>* ahrs[6] = {&col("ahrs_phi"), &col("ahrs_theta"), &col("ahrs_psi"),
                                  &col("ahrs_p"),   &col("ahrs_q"),     &col("ahrs_r")};
  std::vector<double>* range[kBeacons] = {&col("range1"), &col("range2"), &col("range3"),
                                          &col("range4")};
  std::vector<double>* outlier[kBeacons] = {&col("outlier1"), &col("outlier2"), &col("outlier3"),
                                            &col("outlier4")};
  auto& depth = col("depth");
  std::vector<double>* truth[4] = {&col("x_true"), &col("y_true"), &col("z_true"),
                                   &col("psi_true")};
  std::vector<double>* cmd[3] = {&col("x_cmd"), &col("y_cmd"), &col("z_cmd")};

  // Motion (Table 1), generated forward in time alongside the rows: u(t_j) = u_cmd + n_u,
  // x(t_{j+1}) = motion_model(u(t_j), x(t_j)); the command alone gives the command trajectory.
  // A row's pose is propagated from the motion sample t_j <= t (Tables 5–6, lines 5–6).
  std::vector<Vec<6>> row_pose(n), row_vel(n);
  Vec<6> pose = Vec<6>::Zero(), pose_cmd = Vec<6>::Zero(), vel;
  std::size_t j = 0;
  auto draw_velocity = [&] {
    for (int i = 0; i < 6; ++i) {
      vel(i) = p.command(i) + (p.motion_sigma(i) > 0.0 ? p.motion_sigma(i) * motion.gauss() : 0.0);
    }
  };
  draw_velocity();
  for (std::size_t k = 0; k < n; ++k) {
    const auto jk = static_cast<std::size_t>(std::max(0.0, std::floor(row_t[k] / kMotionDt_s)));
    while (j < jk) {
      pose = motion_model(pose, vel, kMotionDt_s);
      pose_cmd = motion_model(pose_cmd, p.command, kMotionDt_s);
      draw_velocity();
      ++j;
    }
    const double dt = row_t[k] - static_cast<double>(j) * kMotionDt_s;
    t[k] = row_t[k];
    row_pose[k] = motion_model(pose, vel, dt);
    row_vel[k] = vel;
    const Vec<6> c = motion_model(pose_cmd, p.command, dt);
    for (int i = 0; i < 3; ++i)
      (*truth[i])[k] = row_pose[k](i);
    (*truth[3])[k] = row_pose[k](5);
    for (int i = 0; i < 3; ++i)
      (*cmd[i])[k] = c(i);
  }

  // Correlated range noise n_c (Table 7): one draw per t_gap window, shared by all ranges.
  const auto windows = static_cast<std::size_t>(std::floor(p.duration_s / p.t_gap_s)) + 2;
  std::vector<double> n_c(windows, 0.0);
  if (p.sigma_corr_m > 0.0) {
    for (double& v : n_c)
      v = p.sigma_corr_m * corr.gauss();
  }

  // Measurements at each sensor time (eq. 1–3 plus n_c).
  std::vector<std::pair<std::size_t, int>> range_samples;  // (row, beacon) for Table 8
  for (std::size_t e = 0; e < events.size(); ++e) {
    const auto k = static_cast<std::size_t>(row_of_event[e]);
    const int s = events[e].second;
    const Vec<6>& x = row_pose[k];
    const Vec<6>& u = row_vel[k];
    if (s == kDvl) {
      for (int i = 0; i < 3; ++i)
        (*dvl[i])[k] = u(i) + p.velocity_sigma(i) * sensor.gauss();
    } else if (s == kAhrs) {
      for (int i = 0; i < 3; ++i) {
        const double a = x(3 + i) + p.attitude_sigma_rad * sensor.gauss();
        (*ahrs[i])[k] = i == 2 ? wrap_pi(a) : a;
      }
      for (int i = 3; i < 6; ++i)
        (*ahrs[i])[k] = u(i) + p.velocity_sigma(i) * sensor.gauss();
    } else if (s == kDepth) {
      depth[k] = x(2) + p.sigma_depth_m * sensor.gauss();
    } else {
      const int b = s - kRange1;
      const double noise = p.sigma_range_m * sensor.gauss();
      if (p.range_dropout > 0.0 && drop.uniform() < p.range_dropout) continue;
      const auto w = std::min(static_cast<std::size_t>(t[k] / p.t_gap_s), windows - 1);
      const auto bi = static_cast<std::size_t>(b);
      (*range[bi])[k] = (beacons()[bi] - x.head<3>()).norm() + noise + n_c[w];
      (*outlier[bi])[k] = 0.0;
      range_samples.emplace_back(k, b);
    }
  }

  // Outliers (Table 8): N range samples drawn without replacement get ±σ_o.
  const std::size_t n_out =
      std::min(range_samples.size(), static_cast<std::size_t>(std::max(0, p.outliers)));
  for (std::size_t i = 0; i < n_out; ++i) {
    std::swap(range_samples[i], range_samples[outlier_draws.pick(i, range_samples.size() - 1)]);
    const auto [k, b] = range_samples[i];
    const double offset = outlier_draws.uniform() < 0.5 ? -p.outlier_m : p.outlier_m;
    (*range[static_cast<std::size_t>(b)])[k] += offset;
    (*outlier[static_cast<std::size_t>(b)])[k] = offset;
  }
  return d;
}

}  // namespace kfw::underwater
