#include "filter/dare.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <string>

namespace kfw {

Expected<SteadyState> solve_dare(const MatX& F, const MatX& H, const MatX& Q, const MatX& R,
                                 const DareOptions& options) {
  const Eigen::Index n = F.rows();
  if (F.cols() != n || Q.rows() != n || Q.cols() != n || H.cols() != n || R.rows() != H.rows() ||
      R.cols() != H.rows()) {
    return Error{"DARE: matrix sizes do not agree"};
  }
  if (!F.allFinite() || !H.allFinite() || !Q.allFinite() || !R.allFinite()) {
    return Error{"DARE: a matrix holds NaN or infinity"};
  }
  Eigen::LLT<MatX> r_llt(R);
  if (r_llt.info() != Eigen::Success) return Error{"DARE: R is not positive definite"};

  // Dual control form X = A^T X (I + G X)^{-1} A + Hq with A = F^T, G = H^T R^{-1} H, Hq = Q.
  MatX A = F.transpose();
  MatX G = H.transpose() * r_llt.solve(H);
  MatX X = Q;
  const MatX I = MatX::Identity(n, n);
  SteadyState out;
  for (int k = 1; k <= options.max_iterations; ++k) {
    Eigen::PartialPivLU<MatX> W(I + G * X);
    const MatX WinvA = W.solve(A);
    const MatX WinvG = W.solve(G);
    const MatX X_next = X + A.transpose() * X * WinvA;
    G = G + A * WinvG * A.transpose();
    A = A * WinvA;
    G = 0.5 * (G + G.transpose()).eval();
    const double change = (X_next - X).norm();
    X = 0.5 * (X_next + X_next.transpose());
    if (!X.allFinite()) return Error{"DARE: the doubling iteration diverged"};
    out.iterations = k;
    if (change <= options.tolerance * (1.0 + X.norm())) break;
    if (k == options.max_iterations) {
      return Error{"DARE: no convergence in " + std::to_string(k) + " doublings"};
    }
  }
  out.P_pred = X;
  const MatX S = H * X * H.transpose() + R;
  Eigen::LLT<MatX> s_llt(S);
  if (s_llt.info() != Eigen::Success) return Error{"DARE: S is not positive definite"};
  out.K = s_llt.solve(H * X).transpose();
  const MatX IKH = I - out.K * H;
  out.P_post = IKH * X * IKH.transpose() + out.K * R * out.K.transpose();
  return out;
}

}  // namespace kfw
