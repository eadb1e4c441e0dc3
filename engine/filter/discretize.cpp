#include "filter/discretize.h"

#include <Eigen/LU>
#include <cmath>
#include <string>

namespace kfw {

MatX expm(const MatX& M) {
  const Eigen::Index n = M.rows();
  // Scale so that ||M / 2^s||_1 <= 1/2, where 18 Taylor terms reach double precision.
  const double norm = M.cwiseAbs().colwise().sum().maxCoeff();
  int s = 0;
  if (norm > 0.5) s = static_cast<int>(std::ceil(std::log2(norm / 0.5)));
  const MatX X = M / std::ldexp(1.0, s);
  MatX result = MatX::Identity(n, n);
  MatX term = MatX::Identity(n, n);
  for (int k = 1; k <= 18; ++k) {
    term = (term * X / static_cast<double>(k)).eval();
    result += term;
  }
  for (int i = 0; i < s; ++i)
    result = (result * result).eval();
  return result;
}

Expected<Discretized> van_loan(const MatX& A, const MatX& B, const MatX& G, const MatX& Qc,
                               double T_s) {
  const Eigen::Index n = A.rows();
  if (A.cols() != n || n == 0) return Error{"van_loan: A must be square and non-empty"};
  if (!(T_s > 0.0) || !std::isfinite(T_s)) {
    return Error{"van_loan: sample period must be positive and finite, got " + std::to_string(T_s)};
  }
  if (B.size() != 0 && B.rows() != n) return Error{"van_loan: B must have as many rows as A"};
  if (G.rows() != n) return Error{"van_loan: G must have as many rows as A"};
  if (Qc.rows() != G.cols() || Qc.cols() != G.cols()) {
    return Error{"van_loan: Qc must be square with G's column count"};
  }
  if (!A.allFinite() || !G.allFinite() || !Qc.allFinite() || (B.size() && !B.allFinite())) {
    return Error{"van_loan: non-finite entry in A, B, G or Qc"};
  }
  Discretized d;
  MatX C = MatX::Zero(2 * n, 2 * n);
  C.topLeftCorner(n, n) = -A * T_s;
  C.topRightCorner(n, n) = G * Qc * G.transpose() * T_s;
  C.bottomRightCorner(n, n) = A.transpose() * T_s;
  const MatX E = expm(C);
  d.F = E.bottomRightCorner(n, n).transpose();
  d.Q = d.F * E.topRightCorner(n, n);
  d.Q = 0.5 * (d.Q + d.Q.transpose()).eval();
  if (B.size() != 0) {
    const Eigen::Index m = B.cols();
    MatX Cb = MatX::Zero(n + m, n + m);
    Cb.topLeftCorner(n, n) = A * T_s;
    Cb.topRightCorner(n, m) = B * T_s;
    d.Gamma = expm(Cb).topRightCorner(n, m);
  }
  return d;
}

}  // namespace kfw
