// A matrix matcher that prints both matrices and their difference on failure.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <sstream>

namespace kfw::testing {

template <typename A, typename B>
::testing::AssertionResult MatricesNear(const Eigen::MatrixBase<A>& a,
                                        const Eigen::MatrixBase<B>& b, double tol) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure() << "sizes differ: " << a.rows() << "x" << a.cols()
                                         << " vs " << b.rows() << "x" << b.cols();
  }
  const double err = (a - b).cwiseAbs().maxCoeff();
  if (err <= tol) return ::testing::AssertionSuccess();
  std::ostringstream os;
  os << "max |a - b| = " << err << " > " << tol << "\na =\n"
     << a << "\nb =\n"
     << b << "\na - b =\n"
     << (a - b);
  return ::testing::AssertionFailure() << os.str();
}

// True when M is symmetric and its eigenvalues are >= -tol.
template <typename M>
::testing::AssertionResult IsSymmetricPsd(const Eigen::MatrixBase<M>& m, double tol = 1e-9) {
  const double asym = (m - m.transpose()).cwiseAbs().maxCoeff();
  if (asym > tol) return ::testing::AssertionFailure() << "not symmetric by " << asym << "\n" << m;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m.eval().template cast<double>());
  if (es.eigenvalues().minCoeff() < -tol) {
    return ::testing::AssertionFailure() << "eigenvalue " << es.eigenvalues().minCoeff() << "\n"
                                         << m;
  }
  return ::testing::AssertionSuccess();
}

}  // namespace kfw::testing
