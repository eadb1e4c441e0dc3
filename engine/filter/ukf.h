// The unscented Kalman filter of the filter library, additive noise, scaled sigma points (Julier
// 2002; Wan & van der Merwe 2000): λ = α²(n + κ) − n, W0m = λ/(n + λ), W0c = W0m + 1 − α² + β,
// Wi = 1/(2(n + λ)). Angle components (of the state or the measurement) are averaged as the
// central sigma point plus the weighted mean of the wrapped differences from it, and their
// deviations wrapped, so a spread across ±π is handled. The caller propagates the sigma points
// through f and h; the measurement update is the one of measurement_update.h, from C = P_xz.
#pragma once

#include <cmath>
#include <span>

#include "core/types.h"
#include "filter/angle.h"
#include "filter/filter_types.h"

namespace kfw {

struct UkfWeights {
  double c = 0.0;  // n + λ
  double m0 = 0.0, c0 = 0.0, i = 0.0;
  double m(Eigen::Index j) const { return j == 0 ? m0 : i; }
  double cw(Eigen::Index j) const { return j == 0 ? c0 : i; }
  // The scaled weights of n states; n + λ must be positive (the caller checks).
  static UkfWeights scaled(Eigen::Index n, double alpha, double beta, double kappa);
};

// Lower Cholesky factor of a symmetric A (only its lower triangle read): false if A is not
// positive definite. Plain loops: n ≤ 6 on the fixed-size path, where Eigen's LLT costs more to
// compile than to run.
template <class Mat>
bool cholesky_lower(const Mat& A, Mat& L) {
  const Eigen::Index n = A.rows();
  L.setZero();
  for (Eigen::Index j = 0; j < n; ++j) {
    double d = A(j, j);
    for (Eigen::Index k = 0; k < j; ++k)
      d -= L(j, k) * L(j, k);
    if (!(d > 0.0)) return false;
    const double ljj = std::sqrt(d);
    L(j, j) = ljj;
    for (Eigen::Index i = j + 1; i < n; ++i) {
      double v = A(i, j);
      for (Eigen::Index k = 0; k < j; ++k)
        v -= L(i, k) * L(j, k);
      L(i, j) = v / ljj;
    }
  }
  return true;
}

// The symmetric square root of a positive semi-definite A (a singular P, e.g. a state the noise
// does not drive); false if A has an eigenvalue below −1e-9 of its largest.
bool symmetric_sqrt(const MatX& A, MatX& L);

// The 2n + 1 sigma points of N(x, P): x and x ± the columns of √((n + λ) P), columns of X. A P
// that lost definiteness beyond rounding returns false.
template <int N, class Sig>
bool sigma_points(const Vec<N>& x, const Covariance<N>& P, const UkfWeights& w, Sig& X) {
  const Eigen::Index n = x.size();
  const Covariance<N> A = w.c * P;
  Covariance<N> L(n, n);
  if (!cholesky_lower(A, L)) {
    MatX Ls;
    if (!symmetric_sqrt(A, Ls)) return false;
    L = Ls;
  }
  X.col(0) = x;
  for (Eigen::Index j = 0; j < n; ++j) {
    X.col(1 + j) = x + L.col(j);
    X.col(1 + n + j) = x - L.col(j);
  }
  return true;
}

// Weighted mean of the columns of Y, angle rows relative to the central column (circular mean).
template <class Sig, class Out>
void sigma_mean(const Sig& Y, const UkfWeights& w, std::span<const Angle> angle, Out& mean) {
  for (Eigen::Index r = 0; r < Y.rows(); ++r) {
    const Angle a = angle[static_cast<std::size_t>(r)];
    if (a == Angle::kNone) {
      double s = 0.0;
      for (Eigen::Index j = 0; j < Y.cols(); ++j)
        s += w.m(j) * Y(r, j);
      mean(r) = s;
    } else {
      const double ref = Y(r, 0);
      double s = 0.0;
      for (Eigen::Index j = 0; j < Y.cols(); ++j)
        s += w.m(j) * wrap(Y(r, j) - ref, a);
      mean(r) = wrap(ref + s, a);
    }
  }
}

// Column j of Y minus the mean, angle rows wrapped.
template <class Sig, class Mean, class Out>
void sigma_deviation(const Sig& Y, Eigen::Index j, const Mean& mean, std::span<const Angle> angle,
                     Out& d) {
  for (Eigen::Index r = 0; r < Y.rows(); ++r)
    d(r) = wrap(Y(r, j) - mean(r), angle[static_cast<std::size_t>(r)]);
}

// The predicted moments from the propagated sigma points Y_j = f(X_j):
// x⁻ = Σ Wm Y_j, P⁻ = Σ Wc (Y_j − x⁻)(Y_j − x⁻)ᵀ + Q, symmetrised.
template <int N, class Sig, class MatQ>
void unscented_predict(const Sig& Y, const UkfWeights& w, std::span<const Angle> angle,
                       const MatQ& Q, Vec<N>& x, Covariance<N>& P) {
  sigma_mean(Y, w, angle, x);
  P = Q;
  Vec<N> d(x.size());
  for (Eigen::Index j = 0; j < Y.cols(); ++j) {
    sigma_deviation(Y, j, x, angle, d);
    P.noalias() += w.cw(j) * d * d.transpose();
  }
  P = 0.5 * (P + P.transpose()).eval();
}

// The predicted measurement from the sigma points X_j of N(x, P) and Z_j = h(X_j):
// ẑ = Σ Wm Z_j, S = Σ Wc (Z_j − ẑ)(·)ᵀ + R, C = P_xz = Σ Wc (X_j − x)(Z_j − ẑ)ᵀ.
template <int N, int M, int MaxM>
struct UnscentedMeasurement {
  typename FilterDims<N, M, MaxM>::Meas zhat;
  typename FilterDims<N, M, MaxM>::MeasCov S;
  typename FilterDims<N, M, MaxM>::Cross C;
};

template <int N, int M, int MaxM, class SigX, class SigZ, class MatR>
UnscentedMeasurement<N, M, MaxM> unscented_measurement(const SigX& X, const Vec<N>& x,
                                                       const SigZ& Z, const UkfWeights& w,
                                                       std::span<const Angle> state_angle,
                                                       std::span<const Angle> meas_angle,
                                                       const MatR& R) {
  const Eigen::Index n = x.size(), m = Z.rows();
  UnscentedMeasurement<N, M, MaxM> u;
  u.zhat.resize(m);
  sigma_mean(Z, w, meas_angle, u.zhat);
  u.S = R;
  u.C.setZero(n, m);
  typename FilterDims<N, M, MaxM>::Meas dz(m);
  Vec<N> d(n);
  for (Eigen::Index j = 0; j < Z.cols(); ++j) {
    sigma_deviation(Z, j, u.zhat, meas_angle, dz);
    sigma_deviation(X, j, x, state_angle, d);
    u.S.noalias() += w.cw(j) * dz * dz.transpose();
    u.C.noalias() += w.cw(j) * d * dz.transpose();
  }
  return u;
}

}  // namespace kfw
