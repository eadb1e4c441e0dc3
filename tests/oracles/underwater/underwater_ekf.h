// Seed 004, Table 12: EKF localization of the underwater vehicle. State X = (x, y, z), m. Predict
// by dead reckoning with the latest DVL body velocity rotated by the latest AHRS attitude; correct
// with the four beacon ranges and depth. Three update schemes (seed 004, Sec. 4.4): AS applies each
// measurement when it arrives; SC and SI gather the ranges of one synchronous instant (every beacon
// once) and apply them in one stacked update (SC) or one by one (SI). Each range innovation passes
// a χ² gate d² = y²/S ≤ gate² (seed 004, eq. 10, with S for σ_r²).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "core/expected.h"
#include "core/scenario.h"
#include "core/types.h"
#include "oracles/underwater/underwater_sim.h"
#include "oracles/underwater/underwater_stats.h"

namespace kfw::underwater {

static constexpr int kX = 0;
static constexpr int kY = 1;
static constexpr int kZ = 2;

enum class Scheme { kAS = 0, kSC = 1, kSI = 2 };

struct FilterParams {
  Scheme scheme = Scheme::kSC;
  double gate = 2.5;           // reject a range when d = |y|/√S > gate
  double sigma_range_m = 0.1;  // R of a range
  double sigma_depth_m = 0.2;  // R of depth
  double sigma_corr_m = 0.2;   // common range noise σ_c, in R when corr_in_R
  bool corr_in_R = true;       // SC: R = σ_r² I + σ_c² 1 1ᵀ; AS/SI: R = σ_r² + σ_c²
  double q_pos = 0.07;         // position random-walk density, m/√s: Q = q² Δt I
  double sigma0_pos_m = 1.0;   // initial σ of each coordinate, around (0, 0, first depth)
};

// Per-sample outcome, one value per row and sensor (NaN: the sensor did not sample that row).
inline constexpr double kUsed = 0.0;
inline constexpr double kRejected = 1.0;  // failed the χ² gate
inline constexpr double kInvalid = 2.0;   // range ≤ 0, or S not positive definite

struct UnderwaterResult final : RunResult {
  // Estimate and covariance after the row's updates.
  std::vector<double> x, y, z, Pxx, Pyy, Pzz, Pxy, Pxz, Pyz;
  // Truth and command trajectory (NaN where the dataset has none); distance error |X̂ − X|.
  std::vector<double> x_true, y_true, z_true, x_cmd, y_cmd, pos_err;
  // Range innovation y = r − ‖X̂⁻ − B‖ and its S at the row the range arrived (NaN elsewhere).
  std::array<std::vector<double>, kBeacons> innovation, S;
  // Injected outlier offset from the dataset (0: clean; NaN: no sample or unknown).
  std::array<std::vector<double>, kBeacons> injected;
  std::vector<double> depth_innovation, depth_S;
  // Timing raster: kUsed / kRejected / kInvalid per row and sensor (Sensor order), NaN = none.
  std::array<std::vector<double>, kSensorCount> status;
  // Times a sensor was expected but did not sample (a gap over 1.5 median periods).
  std::array<std::vector<double>, kSensorCount> missing_t;
  // Simulated-error statistics of the dataset (when it has truth) and the design values.
  bool has_stats = false;
  ErrorStats stats;
  Covariance<kErrorDims> design = Covariance<kErrorDims>::Zero();
  // NEES of the position estimate against truth, (X̂ − X)ᵀ P⁻¹ (X̂ − X) over the coordinates truth
  // covers (nees_dof of x, y, z; 3 with full truth); NaN where truth is missing.
  std::vector<double> nees;
  double nees_dof = 0.0;
  std::size_t ranges_used = 0, ranges_rejected = 0, ranges_invalid = 0, depth_used = 0;
  // Outlier bookkeeping needs the injected offsets (outlier1..4): without them whether a rejected
  // range was an outlier is unknown, and outliers_known is false (the counts mean nothing).
  bool outliers_known = false;
  std::size_t outliers_injected = 0, outliers_detected = 0, outliers_false_alarm = 0;

  Dataset table() const override;
  // Each range and the depth: NIS and y/√S of the updates that passed the gate.
  std::vector<InnovationChannel> channels() const override;
  NeesSeries nees_series() const override;
  std::vector<StateSeries> states() const override;
};

// Runs the EKF over a dataset with the columns of simulate() (truth optional). Errors name a
// missing column or a non-increasing time.
Expected<UnderwaterResult> run_ekf(const Dataset& d, const FilterParams& p,
                                   const RunControl& control = {});

// Range model h(X) = ‖X − B‖ and its Jacobian H = (X − B)ᵀ / ‖X − B‖ (seed 004, Table 5, line 7).
double predicted_range(const Vec<3>& X, const Vec<3>& B);
Jacobian<1, 3> range_jacobian(const Vec<3>& X, const Vec<3>& B);

}  // namespace kfw::underwater
