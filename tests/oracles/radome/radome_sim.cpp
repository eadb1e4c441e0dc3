// Random streams (core/random.h; presets/models/README.md, "Random numbers"), seeded from
// sim.seed:
//   channel.seeker  three normals per sample, in column order: the noise ν_R on range_m, ν_ψ on
//                   psi_rad, ν_θ on theta_rad (seed 001, eq. 2)
// The trajectory, the weave and the slopes are deterministic.
#include "oracles/radome/radome_sim.h"

#include <cmath>
#include <numbers>
#include <string>

#include "core/random.h"
#include "core/types.h"
#include "oracles/radome/radome_model.h"

namespace kfw::radome {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kG = 9.80665;
constexpr double kWeavePeriodY_s = 20.0;
constexpr double kWeavePeriodZ_s = 14.0;
}  // namespace

double slope_psi_true(double amplitude, double t_s) {
  return amplitude * std::sin(0.03 * kPi * t_s - 0.25 * kPi);
}
double slope_theta_true(double amplitude, double t_s) {
  return amplitude * std::sin(0.03 * kPi * t_s);
}

Expected<Dataset> simulate(const SimParams& p) {
  if (!(p.Ts_s > 0.0) || !(p.duration_s >= p.Ts_s)) {
    return Error{"sim.Ts must be positive and at most sim.duration"};
  }
  const Vec<3> u0(std::cos(p.el0_deg * kDeg) * std::cos(p.az0_deg * kDeg),
                  std::cos(p.el0_deg * kDeg) * std::sin(p.az0_deg * kDeg),
                  std::sin(p.el0_deg * kDeg));
  // Target velocity v_T = v_A x̂ + k u0 with |v_T| = v_target: the LOS would stay put.
  const double b = p.v_aircraft_mps * u0(0);
  const double disc = b * b - p.v_aircraft_mps * p.v_aircraft_mps + p.v_target_mps * p.v_target_mps;
  if (disc < 0.0) {
    return Error{"sim.v_target is too slow to keep the LOS direction (az0, el0) for this aircraft"};
  }
  const double k = -b + std::sqrt(disc);
  const Vec<3> vA(p.v_aircraft_mps, 0.0, 0.0);
  const Vec<3> pT0 = p.range0_m * u0;
  const Vec<3> vT0 = vA + k * u0;
  const double wy = 2.0 * kPi / kWeavePeriodY_s, wz = 2.0 * kPi / kWeavePeriodZ_s;
  const double aT = p.target_g * kG;
  const double ww = 2.0 * kPi / p.weave_period_s;

  const auto n = static_cast<std::size_t>(std::floor(p.duration_s / p.Ts_s + 1e-9)) + 1;
  Dataset d;
  d.source = "simulated radome, seed " + std::to_string(p.seed);
  const char* names[] = {"t",           "range_m",       "psi_rad",    "theta_rad",
                         "psi_a_rad",   "theta_a_rad",   "ax_mps2",    "ay_mps2",
                         "az_mps2",     "x_m",           "y_m",        "z_m",
                         "psi_los_rad", "theta_los_rad", "R_psi_true", "R_theta_true"};
  for (const char* name : names)
    d.add(name, n);
  RandomStream seeker(p.seed, "channel.seeker");
  const double sR = std::sqrt(p.var_range_m2), sA = std::sqrt(p.var_angle_rad2);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * p.Ts_s;
    // Target weave a = g_T cos(ωt) integrates to Δp = g_T (1 − cos ωt) / ω².
    Vec<3> pT = pT0 + vT0 * t;
    pT(1) += aT * (1.0 - std::cos(wy * t)) / (wy * wy);
    pT(2) += aT * (1.0 - std::cos(wz * t)) / (wz * wz);
    const Vec<3> rel = pT - vA * t;
    const double psi_a = p.weave_deg * kDeg * std::sin(ww * t);
    const double theta_a = p.weave_deg * kDeg * std::cos(ww * t);
    const double psi = los_psi(rel), theta = los_theta(rel);
    const double Rp = slope_psi_true(p.amplitude, t), Rt = slope_theta_true(p.amplitude, t);
    d.columns[0][i] = t;
    d.columns[1][i] = rel.norm() + sR * seeker.normal();
    d.columns[2][i] = refract(psi, Rp, psi_a) + sA * seeker.normal();
    d.columns[3][i] = refract(theta, Rt, theta_a) + sA * seeker.normal();
    d.columns[4][i] = psi_a;
    d.columns[5][i] = theta_a;
    d.columns[6][i] = 0.0;
    d.columns[7][i] = 0.0;
    d.columns[8][i] = 0.0;
    d.columns[9][i] = rel(0);
    d.columns[10][i] = rel(1);
    d.columns[11][i] = rel(2);
    d.columns[12][i] = psi;
    d.columns[13][i] = theta;
    d.columns[14][i] = Rp;
    d.columns[15][i] = Rt;
  }
  return d;
}

}  // namespace kfw::radome
