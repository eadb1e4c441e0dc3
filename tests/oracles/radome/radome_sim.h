// The engagement of seed 001, Sec. 3: aircraft and target 10 km apart, 300 / 600 m/s, the target
// weaving at 1 g in y and z, radome slopes varying as eq. 5 (amplitude 0.05) or eq. 7 (0.08).
// Choices the paper leaves open (documented in presets/radome.json):
//  - the aircraft flies straight along x (U = 0) while its body (radome boresight) cones by ±w
//    about its flight path, ψ_a = w sin(2πt/P), θ_a = w cos(2πt/P), w = 30°, P = 4 s: the look
//    angle λ − λ_a swings through ±30° faster than the target model can follow, which is what
//    makes the slope observable, and R·(λ − λ_a) reaches ±1.5° (amplitude 0.05) / ±2.4° (0.08);
//    a constant look angle would only bias the position, and adjacent grid modes (ΔR̄ = 0.0167)
//    would then be ~100 m apart against 10 m of noise, locking the IMM onto one mode;
//  - the target starts at range0 in direction (az0, el0) = (0°, 0°) and flies so that, without its
//    weave, the LOS direction would stay constant (the range opens from 10 to ~30 km);
//  - target weave a_T = g_T [0, cos(2πt/20 s), cos(2πt/14 s)].
#pragma once

#include <cstdint>

#include "core/dataset.h"
#include "core/expected.h"

namespace kfw::radome {

struct SimParams {
  double duration_s = 60.0;
  double Ts_s = 0.05;
  double amplitude = 0.05;  // slope amplitude: eq. 5 (0.05) or eq. 7 (0.08)
  double range0_m = 10000.0;
  double az0_deg = 0.0;
  double el0_deg = 0.0;
  double v_aircraft_mps = 300.0;
  double v_target_mps = 600.0;
  double target_g = 1.0;
  double weave_deg = 30.0;
  double weave_period_s = 4.0;
  double var_range_m2 = 1e-6;    // ν_R ~ N(0, 1e-6)
  double var_angle_rad2 = 1e-6;  // ν_ψ, ν_θ ~ N(0, 1e-6)
  std::uint64_t seed = 1;
};

// Columns: t, range_m, psi_rad, theta_rad (measurements, eq. 2), psi_a_rad, theta_a_rad (aircraft
// attitude), ax_mps2, ay_mps2, az_mps2 (aircraft acceleration U), and truth: x_m, y_m, z_m,
// psi_los_rad, theta_los_rad, R_psi_true, R_theta_true.
Expected<Dataset> simulate(const SimParams& p);

// Truth slopes of eq. 5 / eq. 7.
double slope_psi_true(double amplitude, double t_s);
double slope_theta_true(double amplitude, double t_s);

}  // namespace kfw::radome
