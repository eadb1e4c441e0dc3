// The Kalman filter of the filter library (seed 000 eq. 6–9): a functional linear filter — every
// step returns a new Gaussian, so a replay can keep one state per step — on top of the in-place
// pieces the model engine's KF and EKF run on (predict_covariance, innovation_covariance and the
// one measurement update of measurement_update.h, in Joseph form). Fixed sizes where known (fast),
// Eigen::Dynamic works too.
#pragma once

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

#include "core/types.h"
#include "filter/measurement_update.h"

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
  bool ok = false;  // false when the update was not applied (see status)
  UpdateStatus status = UpdateStatus::kSkipped;
};

// P_{k|k-1} = F P F^T + Q in place; FP is scratch, kept by the caller so that a dynamic size does
// not allocate per step.
template <class MatP, class MatF, class MatQ>
[[gnu::always_inline]] inline void predict_covariance(MatP& P, const MatF& F, const MatQ& Q,
                                                      MatP& FP) {
  FP.noalias() = F * P;
  P.noalias() = FP * F.transpose();
  P += Q;
}

// C = P H^T and S = H C + R of a linear(ised) measurement (seed 000 eq. 8).
template <class MatP, class MatH, class MatR, class MatC, class MatS>
void innovation_covariance(const MatP& P, const MatH& H, const MatR& R, MatC& C, MatS& S) {
  C.noalias() = P * H.transpose();
  S.noalias() = H * C;
  S += R;
}

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

// The outcome of the in-place update (measurement_update.h) as the fields of an Update, whose
// post is already the updated Gaussian; K is zero where the update was not applied.
template <int N, int M, int MaxM>
void set_outcome(Update<N, M>& u, const MeasurementUpdate<N, M, MaxM>& m) {
  u.innovation = m.y;
  u.status = m.status;
  u.ok = m.updated();
  u.nis = m.nis;
  if (u.ok) {
    u.K = m.K;
  } else {
    u.K.setZero(u.post.x.rows(), m.y.rows());
  }
}

// The update from an innovation y = z - ẑ with rules (angles, gate): measurement_update.h in Joseph
// form, P = (I - K H) P (I - K H)^T + K R K^T, then forced symmetry.
template <int N, int M>
Update<N, M> update_innovation(const Gaussian<N>& prior, const Vec<M>& y, const Mat<M, N>& H,
                               const Covariance<M>& R, const UpdateRules& rules) {
  Update<N, M> u;
  Mat<N, M> PHt;
  innovation_covariance(prior.P, H, R, PHt, u.S);
  u.post = prior;
  set_outcome(u, update(u.post.x, u.post.P, y, u.S, PHt, rules, H, R));
  return u;
}

// The linear update from z: y = z - H x_{k|k-1}; stays symmetric PSD in floating point where the
// short form P - K H P does not.
template <int N, int M>
Update<N, M> update(const Gaussian<N>& prior, const Vec<M>& z, const Mat<M, N>& H,
                    const Covariance<M>& R) {
  Vec<M> y;
  y.noalias() = z - H * prior.x;
  return update_innovation(prior, y, H, R, UpdateRules{.log_det = false});
}

// Scalar-measurement specialisation of the Joseph update (no LLT): the hot path of 1-D sensors.
template <int N>
Update<N, 1> update_scalar(const Gaussian<N>& prior, double z, const Mat<1, N>& H, double R) {
  Update<N, 1> u;
  const Vec<N> PHt = prior.P * H.transpose();
  const double S = H.dot(PHt) + R;
  u.S(0, 0) = S;
  u.post = prior;
  set_outcome(
      u, update(u.post.x, u.post.P, z - H.dot(prior.x), S, PHt, UpdateRules{.log_det = false}));
  return u;
}

}  // namespace kfw
