// Steady-state Kalman gain of any LTI model from the discrete algebraic Riccati equation.
#pragma once

#include "core/expected.h"
#include "core/types.h"

namespace kfw {

struct SteadyState {
  MatX P_pred;  // P_{k|k-1} at steady state, the DARE solution
  MatX P_post;  // P_{k|k}
  MatX K;       // K = P_pred H^T (H P_pred H^T + R)^{-1}
  int iterations = 0;
};

struct DareOptions {
  int max_iterations = 200;
  double tolerance = 1e-13;  // relative change of the solution between doublings
};

// Solves P = F P F^T - F P H^T (H P H^T + R)^{-1} H P F^T + Q by the structured doubling algorithm
// (Chu, Fan, Lin 2005) on the dual control DARE (A = F^T, B = H^T). Converges quadratically for a
// stabilisable, detectable model and linearly when a unit-circle mode is not driven by Q (the
// constant-bias model of seed 000). Fails with a message when R is not positive definite or the
// iteration diverges.
Expected<SteadyState> solve_dare(const MatX& F, const MatX& H, const MatX& Q, const MatX& R,
                                 const DareOptions& options = {});

}  // namespace kfw
