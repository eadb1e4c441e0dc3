// A covariance is symmetric positive semi-definite (issue 16): checked after every Kalman update in
// builds without NDEBUG (Debug, and the fuzz build of `make fuzz`, whose -O1 -g1 flags keep
// asserts), free in Release. The fuzz harnesses call is_symmetric_psd on what a result exposes.
#pragma once

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace kfw {

// True when P is symmetric and PSD up to rounding: |P − Pᵀ| ≤ tol·s entrywise and the smallest
// eigenvalue ≥ −tol·max(max|λ|, s), s = max(max|P|, reference). `reference` is the largest entry
// of the covariance an update started from: an update subtracts terms of that size, so its
// rounding is relative to it, not to the result (an unstable process grows the prior by 10¹⁰ and
// more while an update brings the measured state back to R's size). A non-finite P is not this
// check's business (the run reports a non-finite result with its step and time) and passes.
template <class M>
bool is_symmetric_psd(const M& P, double tol = 1e-8, double reference = 0.0) {
  if (P.rows() != P.cols()) return false;
  if (P.rows() == 0 || !P.allFinite()) return true;
  const double scale = std::max(P.cwiseAbs().maxCoeff(), reference);
  if (scale == 0.0) return true;
  // In units of `scale`: a P near the largest double (an unstable process) would overflow in
  // P + Pᵀ and in the eigen-solver's squares, and fail the check for the arithmetic's sake.
  using Dense = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic>;
  const Dense Pn = Dense(P) / scale;
  if ((Pn - Pn.transpose()).cwiseAbs().maxCoeff() > tol) return false;
  const Dense S = 0.5 * (Pn + Pn.transpose());
  const Eigen::SelfAdjointEigenSolver<Dense> es(S, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) return false;
  const auto& ev = es.eigenvalues();
  const double top =
      std::max({std::abs(ev.minCoeff()), std::abs(ev.maxCoeff()), reference / scale});
  return ev.minCoeff() >= -tol * top;
}

// The reference scale of an update's prior for debug_check_covariance: max|P| in builds that
// check, nothing in Release.
template <class M>
double debug_prior_scale([[maybe_unused]] const M& P) {
#ifndef NDEBUG
  return P.size() == 0 || !P.allFinite() ? 0.0 : P.cwiseAbs().maxCoeff();
#else
  return 0.0;
#endif
}

// Debug builds: abort with the place when a covariance is not symmetric PSD (to the rounding of
// an update from a prior of scale `reference`, see is_symmetric_psd).
template <class M>
void debug_check_covariance([[maybe_unused]] const M& P, [[maybe_unused]] const char* where,
                            [[maybe_unused]] double reference = 0.0) {
#ifndef NDEBUG
  // A covariance that overflowed is the input's breakdown, not a bug: the model run stops on it
  // with exit 1 naming the state (model_filter_detail.h, check_variances).
  if (!P.allFinite()) return;
  if (!is_symmetric_psd(P, 1e-8, reference)) {
    std::fprintf(stderr, "kfw: covariance not symmetric PSD after %s\n", where);
    std::abort();
  }
#endif
}

}  // namespace kfw
