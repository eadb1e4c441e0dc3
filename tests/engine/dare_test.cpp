#include "filter/dare.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/matrix_matchers.h"

namespace kfw {
namespace {

using testing::MatricesNear;

// The solution satisfies the Riccati equation it solves.
TEST(Dare, SolutionSatisfiesRiccati) {
  MatX F(3, 3), H(2, 3), Q(3, 3), R(2, 2);
  F << 0.9, 0.1, 0, 0, 0.95, 0.2, 0.05, 0, 0.8;
  H << 1, 0, 0, 0, 0, 1;
  Q << 0.3, 0.05, 0, 0.05, 0.2, 0, 0, 0, 0.1;
  R << 0.5, 0.1, 0.1, 0.4;
  auto ss = solve_dare(F, H, Q, R);
  ASSERT_TRUE(ss.ok()) << ss.error();
  const MatX& P = ss->P_pred;
  const MatX S = H * P * H.transpose() + R;
  const MatX rhs =
      F * P * F.transpose() - F * P * H.transpose() * S.inverse() * H * P * F.transpose() + Q;
  EXPECT_TRUE(MatricesNear(P, rhs, 1e-10));
  EXPECT_LT(ss->iterations, 30);
}

// Scalar random walk: p = (q + sqrt(q^2 + 4 q r)) / 2 in closed form.
TEST(Dare, ScalarRandomWalkClosedForm) {
  const double q = 0.7, r = 2.0;
  MatX F = MatX::Identity(1, 1), H = MatX::Identity(1, 1), Q(1, 1), R(1, 1);
  Q << q;
  R << r;
  auto ss = solve_dare(F, H, Q, R);
  ASSERT_TRUE(ss.ok());
  EXPECT_NEAR(ss->P_pred(0, 0), (q + std::sqrt(q * q + 4 * q * r)) / 2, 1e-12);
}

TEST(Dare, RejectsBadInput) {
  MatX F = MatX::Identity(2, 2), H(1, 2), Q = MatX::Identity(2, 2), R(1, 1);
  H << 1, 0;
  R << 0.0;
  auto bad_r = solve_dare(F, H, Q, R);
  ASSERT_FALSE(bad_r.ok());
  EXPECT_NE(bad_r.error().find("R is not positive definite"), std::string::npos);
  R << 1.0;
  MatX Fnan = F;
  Fnan(0, 1) = std::nan("");
  EXPECT_FALSE(solve_dare(Fnan, H, Q, R).ok());
  EXPECT_FALSE(solve_dare(F, MatX::Identity(2, 3), Q, R).ok());
}

}  // namespace
}  // namespace kfw
