// What a `ballbeam` run hands to plots and metrics: the primary run's per-step trace, the three
// closed-loop variants for the step-response overlay (Figs. 8, 9), and the gain operating point.
#pragma once

#include <vector>

#include "core/scenario.h"
#include "scenarios/ballbeam/ballbeam_loop.h"

namespace kfw::ballbeam {

struct BallbeamResult final : RunResult {
  LoopTrace trace;  // the run with the chosen `detection` (closed loop) or the replayed log
  bool closed_loop = true;
  // Closed loop only: true ball position of the noise-free run and of the runs with the
  // detection circuit on and off (same seed, same disturbances), per step.
  std::vector<double> x_noise_free, x_detect_on, x_detect_off;
  std::vector<double> x_hat_detect_on, x_hat_detect_off;
  // Closed loop only: the time grid of the variants above (the whole run; a variant whose ball
  // fell is NaN after the fall, while `t` ends with the chosen run).
  std::vector<double> t_loop;
  bool detection_on = true;  // closed loop: `trace` is the run with detection on
  // Operating point of the tuning.
  double Ts_s = 0.0, lambda = 0.0, alpha = 0.0, beta = 0.0;
  double alpha_dare = 0.0, beta_dare = 0.0;
  double step_time_s = 0.0;

  Dataset table() const override;
  // The position sensor: NIS and y/√S of the updates (flagged samples are not updates).
  std::vector<InnovationChannel> channels() const override;
  // NEES of [x, ẋ] against the simulated truth (closed loop).
  NeesSeries nees_series() const override;
  std::vector<StateSeries> states() const override;
};

}  // namespace kfw::ballbeam
