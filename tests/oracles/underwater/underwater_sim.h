// Seed 004: the sensor-measurement simulator of an underwater vehicle. Motion from velocity
// commands plus Gaussian motion noise (Table 1), sensor clocks with timing jitter (Table 2), DVL,
// AHRS, four beacon ranges and depth at each sensor time (Tables 4–6) with Gaussian noise (eq.
// 1–3), correlated range noise (Table 7) and outliers (Table 8). Seeded and reproducible.
//
// Frame: x north, y east, z down (depth = z, m); attitude (φ, θ, ψ) in rad, Z-Y-X Euler angles;
// body velocities (u, v, w) in m/s, body rates (p, q, r) in rad/s.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "core/dataset.h"
#include "core/types.h"

namespace kfw::underwater {

inline constexpr int kBeacons = 4;
// Beacon positions (x, y, z), m. The paper does not give them; these surround the default helix
// (radius ≈ 1 m, 0 → 36 m deep): two near the surface, two near the bottom, on a 30 m square,
// so the ranges also constrain depth.
inline const std::array<Vec<3>, kBeacons>& beacons() {
  static const std::array<Vec<3>, kBeacons> b = {Vec<3>(15.0, 15.0, 5.0), Vec<3>(-15.0, 15.0, 40.0),
                                                 Vec<3>(-15.0, -15.0, 5.0),
                                                 Vec<3>(15.0, -15.0, 40.0)};
  return b;
}

// Motion is integrated at this period (the 0.01 s matching window of Tables 4–6).
inline constexpr double kMotionDt_s = 0.01;
// Sensor times are snapped to this grid so that sensors sharing a clock share a row.
inline constexpr double kTimeGrid_s = 1e-6;

// The sensors of the CSV and of the timing raster, in this order.
enum Sensor { kDvl = 0, kAhrs, kRange1, kRange2, kRange3, kRange4, kDepth, kSensorCount };
const char* sensor_name(int s);  // "dvl", "ahrs", "range1", ..., "depth"

struct SimParams {
  std::uint64_t seed = 4;
  double duration_s = 180.0;
  bool synchronous = false;  // one clock for every sensor (period dt_sync_s), else Table 3
  double dt_sync_s = 0.1;
  // Table 3 periods, s: DVL, AHRS, range1..4, depth.
  std::array<double, kSensorCount> period_s = {0.20, 0.01, 0.10, 0.10, 0.10, 0.10, 0.02};
  double sigma_t_s = 0.0;  // timing jitter n_t (Table 2)
  // Velocity command (u, v, w, p, q, r) and motion noise σ (Table 9).
  Vec<6> command = (Vec<6>() << 0.5, 0.0, 0.2, 0.0, 0.0, 0.5).finished();
  Vec<6> motion_sigma = (Vec<6>() << 0.10, 0.0, 0.15, 0.0, 0.0, 0.10).finished();
  // Sensor noise σ_s,u on (u, v, w, p, q, r) (Table 10); attitude noise of the AHRS, rad.
  Vec<6> velocity_sigma = (Vec<6>() << 0.1, 0.0, 0.1, 0.0, 0.0, 0.1).finished();
  double attitude_sigma_rad = 0.0;
  double sigma_range_m = 0.1;  // n_r (eq. 2)
  double sigma_depth_m = 0.2;  // n_d (eq. 3)
  double sigma_corr_m = 0.0;   // n_c, common to all ranges (Table 7)
  double t_gap_s = 1.0;        // n_c is redrawn every t_gap
  int outliers = 0;            // N range samples drawn at random (Table 8)
  double outlier_m = 1.0;      // their offset ±σ_o, sign drawn at random
  double range_dropout = 0.0;  // probability that a range sample is lost (an empty cell)
};

// The pose after dead reckoning body velocity ν and rates ω over dt (6-DOF Euler kinematics,
// midpoint attitude): x(t) = motion_model(u(t), x(t-1)) of Table 1.
Vec<6> motion_model(const Vec<6>& pose, const Vec<6>& velocity, double dt_s);
// Rotation body → world for Z-Y-X Euler angles.
Mat<3> rotation(double phi, double theta, double psi);

// Columns: t; dvl_u, dvl_v, dvl_w (m/s); ahrs_phi, ahrs_theta, ahrs_psi (rad), ahrs_p, ahrs_q,
// ahrs_r (rad/s); range1..4 (m); depth (m); x_true, y_true, z_true (m), psi_true (rad); x_cmd,
// y_cmd, z_cmd (m, the noise-free command trajectory); outlier1..4 (injected offset, m, 0 when
// clean, empty where that range did not sample). One row per measurement time; empty cells where
// a sensor did not sample.
Dataset simulate(const SimParams& p);

}  // namespace kfw::underwater
