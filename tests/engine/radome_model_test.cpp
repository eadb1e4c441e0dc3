#include "oracles/radome/radome_model.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/matrix_matchers.h"
#include "filter/discretize.h"

namespace kfw::radome {
namespace {

using kfw::testing::IsSymmetricPsd;
using kfw::testing::MatricesNear;

TEST(RadomeModel, AxisModelMatchesClosedForm) {
  // Singer-type block: F = [[1, T, τ²(T/τ − 1 + e^{−T/τ})], [0, 1, τ(1 − e^{−T/τ})], [0, 0,
  // e^{−T/τ}]].
  const double tau = 2.0, T = 0.05, q = 3.0;
  auto m = axis_model(tau, q, T);
  ASSERT_TRUE(m.ok()) << m.error();
  const double e = std::exp(-T / tau);
  Mat<3> F;
  F << 1, T, tau * tau * (T / tau - 1 + e), 0, 1, tau * (1 - e), 0, 0, e;
  EXPECT_TRUE(MatricesNear(m->F, F, 1e-13));
  // The input B = [0, −1, 0]^T enters like a double integrator: Γ = [−T²/2, −T, 0]^T.
  EXPECT_TRUE(MatricesNear(m->Gamma, Vec<3>(-T * T / 2, -T, 0), 1e-14));
  // Acceleration variance of the discrete noise: q/τ² · τ/2 (1 − e^{−2T/τ}).
  EXPECT_NEAR(m->Q(2, 2), q / (tau * tau) * tau / 2 * (1 - std::exp(-2 * T / tau)), 1e-13);
  EXPECT_TRUE(IsSymmetricPsd(m->Q, 1e-15));
}

TEST(RadomeModel, FullModelIsThreeCopiesOfTheAxisBlock) {
  auto m = axis_model(1.5, 2.0, 0.1);
  ASSERT_TRUE(m.ok());
  const Mat<9> F = full_F(*m);
  const Covariance<9> Q = full_Q(*m);
  for (int ax = 0; ax < 3; ++ax) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        EXPECT_EQ(F(3 * i + ax, 3 * j + ax), m->F(i, j));
        EXPECT_EQ(Q(3 * i + ax, 3 * j + ax), m->Q(i, j));
      }
    }
  }
  // The same as discretising eq. 1 in one piece.
  MatX A = MatX::Zero(9, 9), D = MatX::Zero(9, 3);
  A.block(0, 3, 3, 3).setIdentity();
  A.block(3, 6, 3, 3).setIdentity();
  A.block(6, 6, 3, 3) = -MatX::Identity(3, 3) / 1.5;
  D.block(6, 0, 3, 3) = MatX::Identity(3, 3) / 1.5;
  auto d = van_loan(A, MatX(), D, 2.0 * MatX::Identity(3, 3), 0.1);
  ASSERT_TRUE(d.ok());
  EXPECT_TRUE(MatricesNear(MatX(F), d->F, 1e-13));
  EXPECT_TRUE(MatricesNear(MatX(Q), d->Q, 1e-13));
}

TEST(RadomeModel, SlopeCorrectionInvertsRefraction) {
  const double los = 0.6, att = -0.1, R = 0.043;
  EXPECT_NEAR(undo_slope(refract(los, R, att), R, att), los, 1e-15);
  EXPECT_NEAR(refract(los, 0.0, att), los, 0.0);
}

TEST(RadomeModel, PseudoMeasurementInvertsLosAngles) {
  const Vec<3> rel(7000, 5000, 3000);
  const Vec<3> Y = pseudo_measurement(rel.norm(), los_psi(rel), los_theta(rel));
  EXPECT_TRUE(MatricesNear(Y, rel, 1e-9));
}

TEST(RadomeModel, PseudoCovarianceMatchesNumericalJacobian) {
  const double r = 9000, psi = 0.5, th = 0.3, vR = 4.0, vP = 1e-6, vT = 2e-6;
  Mat<3> J;
  const double h[3] = {1e-3, 1e-8, 1e-8};
  for (int c = 0; c < 3; ++c) {
    double a[3] = {r, psi, th}, b[3] = {r, psi, th};
    a[c] += h[c];
    b[c] -= h[c];
    J.col(c) =
        (pseudo_measurement(a[0], a[1], a[2]) - pseudo_measurement(b[0], b[1], b[2])) / (2 * h[c]);
  }
  const Covariance<3> expected = J * Vec<3>(vR, vP, vT).asDiagonal() * J.transpose();
  const Covariance<3> R = pseudo_covariance(r, psi, th, vR, vP, vT);
  EXPECT_TRUE(MatricesNear(R, expected, 1e-5));
  EXPECT_TRUE(IsSymmetricPsd(R, 1e-9));
}

TEST(RadomeModel, RefractionErrorIsTheAngleBetweenDirections) {
  // Only the azimuth refracts: α = |R_ψ (ψ − ψ_a)|.
  EXPECT_NEAR(refraction_error(0.05, 0.0, 0.6, 0.2, 0.1, 0.0), 0.05 * 0.5, 1e-12);
  EXPECT_NEAR(refraction_error(0.0, -0.05, 0.6, 0.4, 0.1, 0.0), 0.05 * 0.4, 1e-12);
  EXPECT_EQ(refraction_error(0.0, 0.0, 0.6, 0.4, 0.1, 0.0), 0.0);
}

TEST(RadomeModel, GridFollowsEq6) {
  const auto g = grid_axis(-0.05, 0.05, 7);
  ASSERT_EQ(g.size(), 7u);
  EXPECT_DOUBLE_EQ(g.front(), -0.05);
  EXPECT_DOUBLE_EQ(g.back(), 0.05);
  EXPECT_NEAR(g[3], 0.0, 1e-17);
  EXPECT_NEAR(g[1] - g[0], 0.1 / 6, 1e-15);
  const auto one = grid_axis(0.01, 0.03, 1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_DOUBLE_EQ(one[0], 0.02);
}

}  // namespace
}  // namespace kfw::radome
