// The sizes of one filter, so that signatures read like the math: N states (fixed, or
// Eigen::Dynamic), M measurement components (fixed, or Eigen::Dynamic up to MaxM: no heap).
// With fixed sizes these are the types of core/types.h (Vec<N>, Covariance<N>, Gain<N, M>, ...).
#pragma once

#include <Eigen/Core>

#include "core/types.h"

namespace kfw {

// Eigen wants row-major storage for a compile-time row vector.
template <int R, int C>
inline constexpr int kStorage = (R == 1 && C != 1) ? Eigen::RowMajor : Eigen::ColMajor;

template <int N, int M, int MaxM = M>
struct FilterDims {
  using State = Vec<N>;                                        // x
  using StateCov = Covariance<N>;                              // P, F, Q
  using Meas = Eigen::Matrix<double, M, 1, 0, MaxM, 1>;        // z, ẑ, y
  using MeasCov = Eigen::Matrix<double, M, M, 0, MaxM, MaxM>;  // S, R
  // C = P Hᵀ (KF, EKF) or P_xz (UKF), and the gain K = C S⁻¹.
  using Cross = Eigen::Matrix<double, N, M, kStorage<N, M>, N, MaxM>;
  using MeasJac = Eigen::Matrix<double, M, N, kStorage<M, N>, MaxM, N>;  // H = ∂h/∂x
};

}  // namespace kfw
