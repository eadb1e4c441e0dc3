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

// True when P is symmetric and PSD up to rounding: |P − Pᵀ| ≤ tol·max|P| entrywise and the
// smallest eigenvalue ≥ −tol·max(|λ|). A non-finite P is not this check's business (the run
// reports a non-finite result with its step and time) and passes.
template <class M>
bool is_symmetric_psd(const M& P, double tol = 1e-8) {
  if (P.rows() != P.cols()) return false;
  if (P.rows() == 0 || !P.allFinite()) return true;
  const double scale = P.cwiseAbs().maxCoeff();
  if (scale == 0.0) return true;
  if ((P - P.transpose()).cwiseAbs().maxCoeff() > tol * scale) return false;
  using Dense = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic>;
  const Dense S = 0.5 * (Dense(P) + Dense(P).transpose());
  const Eigen::SelfAdjointEigenSolver<Dense> es(S, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) return false;
  const auto& ev = es.eigenvalues();
  const double top = std::max(std::abs(ev.minCoeff()), std::abs(ev.maxCoeff()));
  return ev.minCoeff() >= -tol * top;
}

// Debug builds: abort with the place when a covariance is not symmetric PSD.
template <class M>
void debug_check_covariance([[maybe_unused]] const M& P, [[maybe_unused]] const char* where) {
#ifndef NDEBUG
  if (!is_symmetric_psd(P)) {
    std::fprintf(stderr, "kfw: covariance not symmetric PSD after %s\n", where);
    std::abort();
  }
#endif
}

}  // namespace kfw
