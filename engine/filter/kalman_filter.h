// A functional linear Kalman filter: every step returns a new Gaussian, so a replay can keep one
// state per step. Fixed sizes where known (fast), Eigen::Dynamic works too.
#pragma once

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

#include "core/types.h"
#include "filter/covariance_check.h"

namespace kfw {

template <int N>
struct Gaussian {
  Vec<N> x;
  Covariance<N> P;
};

// The outcome of one measurement update. Keeps the prediction and the predicted measurement so
// innovation, S and NIS are there for metrics.
template <int N, int M>
struct Update {
  Gaussian<N> post;   // x_{k|k}, P_{k|k}; equals the prediction when !ok
  Vec<M> innovation;  // y = z - H x_{k|k-1}
  Covariance<M> S;    // S = H P_{k|k-1} H^T + R
  Gain<N, M> K;       // K = P_{k|k-1} H^T S^{-1}
  double nis = std::numeric_limits<double>::quiet_NaN();  // y^T S^{-1} y
  bool ok = false;  // false when S is not positive definite: the update was skipped
};

// x_{k|k-1} = F x_{k-1|k-1} + B u,  P_{k|k-1} = F P F^T + Q.
template <int N>
Gaussian<N> predict(const Gaussian<N>& g, const Mat<N, N>& F, const Vec<N>& Bu,
                    const Covariance<N>& Q) {
  Gaussian<N> out;
  out.x.noalias() = F * g.x;
  out.x += Bu;
  Mat<N, N> FP;
  FP.noalias() = F * g.P;
  out.P.noalias() = FP * F.transpose();
  out.P += Q;
  return out;
}

// Joseph-form update, P = (I - K H) P (I - K H)^T + K R K^T, then forced symmetry: stays symmetric
// PSD in floating point where the short form P - K H P does not.
template <int N, int M>
Update<N, M> update(const Gaussian<N>& prior, const Vec<M>& z, const Mat<M, N>& H,
                    const Covariance<M>& R) {
  Update<N, M> u;
  const Eigen::Index n = prior.x.rows();
  const Eigen::Index m = z.rows();
  Mat<N, M> PHt;
  PHt.noalias() = prior.P * H.transpose();
  u.S.noalias() = H * PHt;
  u.S += R;
  u.innovation.noalias() = z - H * prior.x;
  Eigen::LLT<Covariance<M>> llt(u.S);
  if (llt.info() != Eigen::Success || !u.S.allFinite()) {
    u.post = prior;
    u.K.setZero(n, m);
    return u;
  }
  u.K.noalias() = llt.solve(PHt.transpose()).transpose();
  u.nis = u.innovation.dot(llt.solve(u.innovation));
  u.post.x = prior.x;
  u.post.x.noalias() += u.K * u.innovation;
  Mat<N, N> IKH = Mat<N, N>::Identity(n, n);
  IKH.noalias() -= u.K * H;
  Mat<N, N> tmp;
  tmp.noalias() = IKH * prior.P;
  u.post.P.noalias() = tmp * IKH.transpose();
  Mat<N, M> KR;
  KR.noalias() = u.K * R;
  u.post.P.noalias() += KR * u.K.transpose();
  u.post.P = 0.5 * (u.post.P + u.post.P.transpose()).eval();
  debug_check_covariance(u.post.P, "a Kalman update");
  u.ok = true;
  return u;
}

// Scalar-measurement specialisation of the Joseph update (no LLT): the hot path of 1-D sensors.
template <int N>
Update<N, 1> update_scalar(const Gaussian<N>& prior, double z, const Mat<1, N>& H, double R) {
  Update<N, 1> u;
  const Vec<N> PHt = prior.P * H.transpose();
  const double S = H.dot(PHt) + R;
  u.S(0, 0) = S;
  const double y = z - H.dot(prior.x);
  u.innovation(0) = y;
  if (!(S > 0.0) || !std::isfinite(S)) {
    u.post = prior;
    u.K.setZero(prior.x.rows(), 1);
    return u;
  }
  u.K = PHt / S;
  u.nis = y * y / S;
  u.post.x = prior.x + u.K * y;
  // Joseph form for a scalar measurement: (I-KH)P(I-KH)^T + K R K^T = P - K PHt^T - PHt K^T + K S
  // K^T.
  u.post.P = prior.P;
  u.post.P.noalias() -= u.K * PHt.transpose();
  u.post.P.noalias() -= PHt * u.K.transpose();
  u.post.P.noalias() += (S * u.K) * u.K.transpose();
  debug_check_covariance(u.post.P, "a scalar Kalman update");
  u.ok = true;
  return u;
}

}  // namespace kfw
