#include "filter/discretize.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/matrix_matchers.h"

namespace kfw {
namespace {

using testing::MatricesNear;

TEST(Expm, MatchesClosedFormRotation) {
  // e^{[[0, −w], [w, 0]]} is the rotation by w.
  const double w = 1.3;
  MatX M(2, 2);
  M << 0, -w, w, 0;
  MatX R(2, 2);
  R << std::cos(w), -std::sin(w), std::sin(w), std::cos(w);
  EXPECT_TRUE(MatricesNear(expm(M), R, 1e-13));
}

TEST(Expm, LargeNormUsesSquaring) {
  MatX M(1, 1);
  M << 12.0;
  EXPECT_NEAR(expm(M)(0, 0), std::exp(12.0), 1e-9 * std::exp(12.0));
}

TEST(VanLoan, DoubleIntegratorWhiteAcceleration) {
  // ẋ = [[0, 1], [0, 0]] x + [0, 1]^T w, E[w w] = q δ: the textbook
  // Q = q [[T³/3, T²/2], [T²/2, T]], F = [[1, T], [0, 1]], Γ = [T²/2, T]^T.
  const double T = 0.7, q = 2.5;
  MatX A = MatX::Zero(2, 2);
  A(0, 1) = 1.0;
  MatX G(2, 1);
  G << 0, 1;
  MatX Qc(1, 1);
  Qc << q;
  auto d = van_loan(A, G, G, Qc, T);
  ASSERT_TRUE(d.ok()) << d.error();
  MatX F(2, 2), Q(2, 2), Gamma(2, 1);
  F << 1, T, 0, 1;
  Q << T * T * T / 3, T * T / 2, T * T / 2, T;
  Q *= q;
  Gamma << T * T / 2, T;
  EXPECT_TRUE(MatricesNear(d->F, F, 1e-13));
  EXPECT_TRUE(MatricesNear(d->Q, Q, 1e-13));
  EXPECT_TRUE(MatricesNear(d->Gamma, Gamma, 1e-13));
}

TEST(VanLoan, FirstOrderMarkov) {
  // ẋ = −x/τ + w: F = e^{−T/τ}, Q = q τ/2 (1 − e^{−2T/τ}).
  const double tau = 3.0, T = 0.4, q = 1.7;
  MatX A(1, 1);
  A << -1.0 / tau;
  MatX G(1, 1);
  G << 1.0;
  MatX Qc(1, 1);
  Qc << q;
  auto d = van_loan(A, MatX(), G, Qc, T);
  ASSERT_TRUE(d.ok());
  EXPECT_NEAR(d->F(0, 0), std::exp(-T / tau), 1e-14);
  EXPECT_NEAR(d->Q(0, 0), q * tau / 2 * (1 - std::exp(-2 * T / tau)), 1e-14);
  EXPECT_EQ(d->Gamma.size(), 0);
}

TEST(VanLoan, RejectsBadInput) {
  MatX A = MatX::Zero(2, 2), G = MatX::Zero(2, 1), Qc = MatX::Ones(1, 1);
  EXPECT_FALSE(van_loan(A, MatX(), G, Qc, 0.0).ok());
  EXPECT_FALSE(van_loan(A, MatX(), G, Qc, std::nan("")).ok());
  EXPECT_FALSE(van_loan(A, MatX(), MatX::Zero(3, 1), Qc, 1.0).ok());
  EXPECT_FALSE(van_loan(A, MatX(), G, MatX::Ones(2, 2), 1.0).ok());
}

}  // namespace
}  // namespace kfw
