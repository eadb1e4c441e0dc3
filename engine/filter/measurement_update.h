// The one measurement update of the filter library (KF, EKF, UKF and the IMM's mode-matched
// filters). It takes what every filter computes in its own way — the innovation y = z − ẑ, its
// covariance S and the cross covariance C (C = P⁻Hᵀ for the KF and EKF, C = P_xz for the UKF) — and
// does, in this one place, what they share: angle components of y wrapped, S factored (LLT), an S
// that is not positive definite skipped, the NIS gate, log det S, K = C S⁻¹, x⁺ = x⁻ + K y and the
// covariance, in Joseph form when H is given, else P⁻ − K S Kᵀ.
#pragma once

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <span>

#include "filter/angle.h"
#include "filter/covariance_check.h"
#include "filter/filter_types.h"

namespace kfw {

enum class UpdateStatus {
  kUpdated,  // x and P updated
  kGated,    // NIS above the gate: y, S and NIS kept, x and P unchanged
  kSkipped,  // S not positive definite (or not finite): x and P unchanged
};

// What the update needs to know about a measurement besides its numbers.
struct UpdateRules {
  std::span<const Angle> angle;  // per component of y; empty: none is an angle
  double gate_nis = 0.0;         // an NIS above this gates the update; 0: no gate
  bool log_det = true;  // compute log det S (the NLL's); off on the functional KF's hot path
  bool gates(double nis) const { return gate_nis > 0.0 && nis > gate_nis; }
};

// The outcome of one update, with what metrics need (Stone Soup's "hypothesis" kept with it).
template <int N, int M, int MaxM = M>
struct MeasurementUpdate {
  using Dims = FilterDims<N, M, MaxM>;
  UpdateStatus status = UpdateStatus::kSkipped;
  typename Dims::Meas y;                                  // y = z − ẑ, angle components wrapped
  typename Dims::MeasCov S;                               // S as given
  typename Dims::Cross K;                                 // K = C S⁻¹; set when updated
  double nis = std::numeric_limits<double>::quiet_NaN();  // yᵀ S⁻¹ y; unless skipped
  double log_det_S = std::numeric_limits<double>::quiet_NaN();  // set when updated
  bool updated() const { return status == UpdateStatus::kUpdated; }
};

namespace update_detail {

// The covariance forms. C-form: P⁺ = P⁻ − K S Kᵀ (from C = P_xz, the UKF's). Joseph form:
// P⁺ = (I − K H) P⁻ (I − K H)ᵀ + K R Kᵀ, symmetric PSD in floating point where P⁻ − K H P⁻ is not.
// Both are then symmetrised.
template <int N, int M, int MaxM, class MatR>
MeasurementUpdate<N, M, MaxM> update(Vec<N>& x, Covariance<N>& P,
                                     const typename FilterDims<N, M, MaxM>::Meas& y,
                                     const typename FilterDims<N, M, MaxM>::MeasCov& S,
                                     const typename FilterDims<N, M, MaxM>::Cross& C,
                                     const UpdateRules& rules,
                                     const typename FilterDims<N, M, MaxM>::MeasJac* H,
                                     const MatR* R) {
  using MeasCov = typename FilterDims<N, M, MaxM>::MeasCov;
  MeasurementUpdate<N, M, MaxM> u;
  u.y = y;
  u.S = S;
  for (std::size_t j = 0; j < rules.angle.size(); ++j) {
    const auto jj = static_cast<Eigen::Index>(j);
    u.y(jj) = wrap(u.y(jj), rules.angle[j]);
  }
  Eigen::LLT<MeasCov> llt(S);
  if (llt.info() != Eigen::Success || !S.allFinite()) return u;
  u.nis = u.y.dot(llt.solve(u.y));
  if (rules.gates(u.nis)) {
    u.status = UpdateStatus::kGated;
    return u;
  }
  if (rules.log_det) {
    double log_det = 0.0;
    for (Eigen::Index j = 0; j < S.rows(); ++j)
      log_det += 2.0 * std::log(llt.matrixLLT()(j, j));
    u.log_det_S = log_det;
  }
  u.K = llt.solve(C.transpose()).transpose();
  const double prior_scale = debug_prior_scale(P);
  x.noalias() += u.K * u.y;
  if (H) {
    const Eigen::Index n = x.rows();
    Covariance<N> IKH = Covariance<N>::Identity(n, n);
    IKH.noalias() -= u.K * *H;
    Covariance<N> tmp;
    tmp.noalias() = IKH * P;
    P.noalias() = tmp * IKH.transpose();
    typename FilterDims<N, M, MaxM>::Cross KR;
    KR.noalias() = u.K * *R;
    P.noalias() += KR * u.K.transpose();
  } else {
    P.noalias() -= u.K * S * u.K.transpose();
  }
  P = 0.5 * (P + P.transpose()).eval();
  debug_check_covariance(P, H ? "a Joseph-form update" : "an update from P_xz", prior_scale);
  u.status = UpdateStatus::kUpdated;
  return u;
}

}  // namespace update_detail

// The UKF's update from C = P_xz: P⁺ = P⁻ − K S Kᵀ, symmetrised (Wan & van der Merwe 2000, eq. 15).
template <int N, int M, int MaxM>
MeasurementUpdate<N, M, MaxM> update(Vec<N>& x, Covariance<N>& P,
                                     const Eigen::Matrix<double, M, 1, 0, MaxM, 1>& y,
                                     const typename FilterDims<N, M, MaxM>::MeasCov& S,
                                     const typename FilterDims<N, M, MaxM>::Cross& C,
                                     const UpdateRules& rules) {
  using MeasCov = typename FilterDims<N, M, MaxM>::MeasCov;
  return update_detail::update<N, M, MaxM, MeasCov>(x, P, y, S, C, rules, nullptr, nullptr);
}

// The KF's and EKF's update from C = P⁻Hᵀ, S = H C + R, in Joseph form (seed 000 eq. 8–9
// generalised).
template <int N, int M, int MaxM, class MatR>
MeasurementUpdate<N, M, MaxM> update(Vec<N>& x, Covariance<N>& P,
                                     const Eigen::Matrix<double, M, 1, 0, MaxM, 1>& y,
                                     const typename FilterDims<N, M, MaxM>::MeasCov& S,
                                     const typename FilterDims<N, M, MaxM>::Cross& C,
                                     const UpdateRules& rules,
                                     const typename FilterDims<N, M, MaxM>::MeasJac& H,
                                     const MatR& R) {
  return update_detail::update<N, M, MaxM, MatR>(x, P, y, S, C, rules, &H, &R);
}

// P ← P − K Cᵀ − C Kᵀ + S K Kᵀ (the Joseph form of a scalar measurement, C = P Hᵀ, K = C/S)
// on the upper triangle, mirrored into the lower: P stays exactly symmetric. The three products
// of the full matrix round differently above and below the diagonal, and that asymmetry adds up
// where P grows by many orders and collapses again (an unstable process; found by the model-file
// fuzzer). The upper triangle is what the full form computes, in the same order.
template <int N>
[[gnu::always_inline]] inline void joseph_scalar(Covariance<N>& P, const Vec<N>& K, const Vec<N>& C,
                                                 double S) {
  const Eigen::Index n = P.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i <= j; ++i) {
      double v = P(i, j) - K(i) * C(j);
      v -= C(i) * K(j);
      v += (S * K(i)) * K(j);
      P(i, j) = v;
      P(j, i) = v;
    }
  }
}

// The same for a scalar measurement, without factorisation: K = C / S, NIS = y² / S, and the
// Joseph form as P⁻ − K Cᵀ − C Kᵀ + K S Kᵀ, which needs neither H nor R (the hot path of 1-D
// sensors; y stays in a register until the end).
template <int N>
[[gnu::always_inline]] inline MeasurementUpdate<N, 1> update(Vec<N>& x, Covariance<N>& P, double y,
                                                             double S, const Vec<N>& C,
                                                             const UpdateRules& rules) {
  MeasurementUpdate<N, 1> u;
  if (!rules.angle.empty()) y = wrap(y, rules.angle[0]);
  u.y(0) = y;
  u.S(0, 0) = S;
  if (!(S > 0.0) || !std::isfinite(S)) return u;
  const double nis = y * y / S;
  u.nis = nis;
  if (rules.gates(nis)) {
    u.status = UpdateStatus::kGated;
    return u;
  }
  u.K = C / S;
  const double prior_scale = debug_prior_scale(P);
  x.noalias() += u.K * y;
  joseph_scalar(P, u.K, C, S);
  if (rules.log_det) u.log_det_S = std::log(S);
  debug_check_covariance(P, "a scalar Kalman update", prior_scale);
  u.status = UpdateStatus::kUpdated;
  return u;
}

}  // namespace kfw
