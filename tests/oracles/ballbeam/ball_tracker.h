// Seed 003: the ball tracking filter (eq. 12–15) as a time-varying KF or as the steady-state
// (α-β) filter; on a flagged (missing) sample the update is skipped and the prediction is the
// output (Fig. 5).
#pragma once

#include <limits>

#include "core/expected.h"
#include "filter/kalman_filter.h"
#include "oracles/ballbeam/alpha_beta.h"

namespace kfw::ballbeam {

enum class FilterKind { kKalman = 0, kSteady = 1 };

struct TrackerParams {
  double Ts_s = 0.01;
  double Q = 0.5;   // (m/s²)², acceleration noise w (eq. 13)
  double R = 4e-6;  // m², position noise v (eq. 13)
  FilterKind kind = FilterKind::kSteady;
  double P0_pos = 1e-2;  // m²
  double P0_vel = 1e-2;  // (m/s)²
};

// The filter's fixed pieces, built once per run.
class BallTracker {
 public:
  // Builds the model and, for the steady filter, K = [α, β/Ts]^T from the closed form (eq. 16).
  static Expected<BallTracker> make(const TrackerParams& p);

  struct Step {
    Gaussian<2> out;  // x̂_k|k when updated, else x̄_k|k-1 (the tracker's output)
    double innovation = std::numeric_limits<double>::quiet_NaN();  // y − H x̄; NaN when skipped
    double S = std::numeric_limits<double>::quiet_NaN();           // H P̄ H^T + R
    double nis = std::numeric_limits<double>::quiet_NaN();
    double K1 = std::numeric_limits<double>::quiet_NaN();  // gain used, NaN when skipped
    double K2 = std::numeric_limits<double>::quiet_NaN();
    bool updated = false;
  };

  // The prior of the first sample: x̄_0 = [x0, 0], P̄_0 = diag(P0_pos, P0_vel).
  Gaussian<2> initial(double x0_m) const;
  // Time update x̄_{k+1} = F x̂_k + G^c u^c_k, P̄ = F P̂ F^T + G Q G^T (seed 003, eq. 15).
  Gaussian<2> predict(const Gaussian<2>& out, double uc_mps2) const;
  // Measurement update with y (eq. 14), or none when `missing`. The steady filter uses the fixed
  // α-β gain and still carries the covariance of that gain (Joseph form, exact for any gain), so
  // S and the ±2σ bands stay honest during missing data.
  Step update(const Gaussian<2>& prior, double y_m, bool missing) const;

  const TrackModel& model() const { return model_; }
  const AlphaBeta& gains() const { return ab_; }
  double lambda() const { return lambda_; }
  const TrackerParams& params() const { return p_; }

 private:
  TrackerParams p_;
  TrackModel model_;
  AlphaBeta ab_;
  double lambda_ = 0.0;
  Mat<2, 1> K_steady_;
};

}  // namespace kfw::ballbeam
