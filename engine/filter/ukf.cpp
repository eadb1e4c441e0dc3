#include "filter/ukf.h"

#include <Eigen/Eigenvalues>

namespace kfw {

UkfWeights UkfWeights::scaled(Eigen::Index n, double alpha, double beta, double kappa) {
  const auto nd = static_cast<double>(n);
  const double lambda = alpha * alpha * (nd + kappa) - nd;
  UkfWeights w;
  w.c = nd + lambda;
  w.m0 = lambda / w.c;
  w.c0 = w.m0 + 1.0 - alpha * alpha + beta;
  w.i = 0.5 / w.c;
  return w;
}

// Dynamic size: a rare path, compiled once.
bool symmetric_sqrt(const MatX& A, MatX& L) {
  Eigen::SelfAdjointEigenSolver<MatX> es(A);
  if (es.info() != Eigen::Success) return false;
  const double scale = es.eigenvalues().cwiseAbs().maxCoeff();
  if (es.eigenvalues().minCoeff() < -1e-9 * scale) return false;
  L = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() *
      es.eigenvectors().transpose();
  return true;
}

}  // namespace kfw
