// The extended Kalman filter of the filter library: the Kalman filter of kalman_filter.h run on the
// Jacobians at the current estimate (Bar-Shalom et al. 2001, §10.3). The caller evaluates f, h and
// their Jacobians; on a linear model (f(x) = F x + B u, h(x) = H x) it is the KF, operation for
// operation. Angle components of the measurement are wrapped and the NIS gate applied by the one
// measurement update (measurement_update.h).
#pragma once

#include "filter/kalman_filter.h"

namespace kfw {

// x_{k|k−1} = f(x_{k−1|k−1}), P_{k|k−1} = F P Fᵀ + Q with F = ∂f/∂x at x_{k−1|k−1}; in place, FP
// scratch (the model engine's KF and EKF step).
template <int N, class MatQ>
void ekf_predict(Vec<N>& x, Covariance<N>& P, const Vec<N>& fx, const Mat<N, N>& F, const MatQ& Q,
                 Covariance<N>& FP) {
  x = fx;
  predict_covariance(P, F, Q, FP);
}

// The same as a value.
template <int N>
Gaussian<N> ekf_predict(const Gaussian<N>& g, const Vec<N>& fx, const Mat<N, N>& F,
                        const Covariance<N>& Q) {
  Gaussian<N> out = g;
  Covariance<N> FP;
  ekf_predict(out.x, out.P, fx, F, Q, FP);
  return out;
}

// y = z − h(x_{k|k−1}) with H = ∂h/∂x at x_{k|k−1}: the Joseph-form update of kalman_filter.h.
template <int N, int M>
Update<N, M> ekf_update(const Gaussian<N>& prior, const Vec<M>& z, const Vec<M>& hx,
                        const Mat<M, N>& H, const Covariance<M>& R, const UpdateRules& rules = {}) {
  return update_innovation(prior, Vec<M>(z - hx), H, R, rules);
}

}  // namespace kfw
