// A gimbal-mounted helicopter near hover: truth attitude, a gyro with bias, bias random walk and
// white noise, and an angle sensor (potentiometer) with white noise. Seeded and reproducible.
#pragma once

#include <cstdint>

#include "core/dataset.h"

namespace kfw::helicopter {

struct SimParams {
  double duration_s = 120.0;
  double Ts_s = 0.020;          // gyro period (seed 000: 20 ms)
  double amplitude_deg = 10.0;  // attitude excursion
  double sigma_gyro = 8.2;      // deg/s, engine running (seed 000: 7.72–8.71)
  double sigma_angle = 1.4;     // deg, engine running (seed 000: 1.37–1.45)
  double bias0 = 1.5;           // deg/s
  double bias_walk = 0.05;      // (deg/s)/√s
  double angle_dropout = 0.0;   // probability an angle sample is missing
  std::uint64_t seed = 1;
  // With a prior (the filter's P0): θ(0) ~ N(0, P0_theta) (the sways shifted by a constant) and
  // b(0) ~ N(0, P0_bias) instead of bias0, drawn from their own stream.
  bool x0_from_prior = false;
  double P0_theta = 100.0, P0_bias = 4.0;
};

// Columns t (s), gyro (deg/s), angle (deg, empty = no sample), truth (deg), bias_truth (deg/s).
Dataset simulate(const SimParams& p);

}  // namespace kfw::helicopter
