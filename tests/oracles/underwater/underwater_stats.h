// Seed 004, Sec. 4.1–4.3: the statistics that verify the simulator — the sample covariance of the
// range and depth errors at synchronous instants, next to the covariance the simulator was asked
// for, and the injected outlier count.
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/types.h"

namespace kfw::underwater {

inline constexpr int kErrorDims = 5;  // range1..4, depth
inline const std::array<std::string, kErrorDims> kErrorLabels = {"range1", "range2", "range3",
                                                                 "range4", "depth"};

struct ErrorStats {
  Covariance<kErrorDims> covariance = Covariance<kErrorDims>::Zero();  // E(X) of eq. 5–9
  Vec<kErrorDims> mean = Vec<kErrorDims>::Zero();
  std::size_t instants = 0;           // synchronous instants used
  std::size_t outlier_instants = 0;   // instants left out because a sample was an injected outlier
  std::size_t outliers_injected = 0;  // range samples with a non-zero outlier offset
};

// The design covariance: σ_r² I + σ_c² 1 1ᵀ on the ranges, σ_d² on depth (seed 004, eq. 5–8).
Covariance<kErrorDims> design_covariance(double sigma_range_m, double sigma_corr_m,
                                         double sigma_depth_m);

// Errors are measurement − truth, the true range from x_true, y_true, z_true and the beacons.
// A synchronous instant is the row at which each of the five sensors has a new sample since the
// previous instant (every row of a synchronous log); its errors are those latest samples. Instants
// holding an injected outlier (outlier1..4 ≠ 0, when present) are left out and counted. Errors name
// the missing column, or too few instants.
Expected<ErrorStats> error_stats(const Dataset& d);

}  // namespace kfw::underwater
