// The indirect KF of seed 000 run over a whole dataset: the gyro propagates every sample, the
// angle sensor updates every m-th sample (when it has one).
#pragma once

#include <cstddef>
#include <vector>

#include "core/scenario.h"
#include "filter/consistency.h"

namespace kfw::helicopter {

struct FilterParams {
  double N_omega = 1.0;   // Q: gyro noise variance, (deg/s)²
  double N_theta = 1.0;   // R: angle noise variance, deg²
  int m = 1;              // angle update every m-th gyro sample
  double gamma = 0.0;     // bias cutoff ratio (0: constant bias)
  double P0_theta = 100;  // deg²
  double P0_bias = 4;     // (deg/s)²
  // The prior mean: θ̂0 = the first angle sample (default), or 0 (with b̂0 = 0 always) when the
  // simulator draws the truth from the prior (preset sim.x0_from_prior).
  bool prior_mean_zero = false;
};

struct HelicopterResult final : RunResult {
  // Inputs, per step.
  std::vector<double> gyro, angle, truth;  // angle: NaN where no sample
  std::vector<double> bias_truth;          // from a simulated dataset; empty otherwise
  // Filter output, per step (post-update when updated, else the prediction).
  std::vector<double> theta, bias, P11, P12, P22;
  // Per step; NaN where no update happened.
  std::vector<double> innovation, S, k1, k2, nis;
  std::size_t updates = 0;
  // Operating point of the current tuning, from the dataset's Ts.
  double Ts_s = 0.0, beta = 0.0, k1_steady = 0.0, p11_over_R_steady = 0.0;
  double k1_closed = 0.0;
  // Consistency of the angle channel: moving-average NIS (window nis_window) and the whiteness of
  // the normalised innovations y/√S.
  std::size_t nis_window = 50;
  std::vector<double> nis_avg;
  // NEES of [θ] (or [θ, b] when the bias truth is known) per step, its moving average, its dof.
  std::vector<double> nees, nees_avg;
  double nees_dof = 1.0;
  Whiteness whiteness;
  // The angle channel as channels() builds it, kept by the scenario's run (empty: built on
  // demand), so finalize_run and the metrics do not take 55 k logarithms again.
  std::vector<InnovationChannel> channel_cache;

  Dataset table() const override;
  std::vector<InnovationChannel> channels() const override;
  NeesSeries nees_series() const override;
  std::vector<StateSeries> states() const override;
};

// Runs the filter; columns must hold t, gyro, angle (NaN = no sample) and optionally truth.
HelicopterResult run_indirect_kf(const std::vector<double>& t, const std::vector<double>& gyro,
                                 const std::vector<double>& angle, const FilterParams& p,
                                 const RunControl& control = {});

}  // namespace kfw::helicopter
