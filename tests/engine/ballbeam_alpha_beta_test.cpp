// Seed 003 steady-state gains: the corrected closed form (eq. 16) against the DARE of the same
// constant-velocity model and the values of seed 003 eq. 16.
#include "oracles/ballbeam/alpha_beta.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/matrix_matchers.h"
#include "filter/kalman_filter.h"

namespace kfw::ballbeam {
namespace {

// Seed 003 eq. 16 (corrected, docs/reproductions.md): α = −(λ² + 8λ − (λ+4)√(λ²+8λ))/8, β = (λ² +
// 4λ − λ√(λ²+8λ))/4.
AlphaBeta printed(double l) {
  const double r = std::sqrt(l * l + 8 * l);
  return {-(l * l + 8 * l - (l + 4) * r) / 8, (l * l + 4 * l - l * r) / 4};
}

TEST(BallbeamAlphaBeta, CancellationFreeFormEqualsPrintedFormula) {
  for (double l : {1e-3, 1e-2, 0.0354, 0.1, 1.0, 10.0, 100.0}) {
    const AlphaBeta a = alpha_beta(l), b = printed(l);
    EXPECT_NEAR(a.alpha, b.alpha, 1e-12 * std::max(1.0, l)) << "λ = " << l;
    EXPECT_NEAR(a.beta, b.beta, 1e-12 * std::max(1.0, l)) << "λ = " << l;
  }
}

TEST(BallbeamAlphaBeta, SpecValues) {
  // Seed 003 eq. 16: λ = 0.0354 → α = 0.2335, β = 0.0310; λ = 0.1 → 0.36, 0.08; λ = 1 → 0.75, 0.50.
  EXPECT_NEAR(alpha_beta(0.0354).alpha, 0.2335, 5e-4);
  EXPECT_NEAR(alpha_beta(0.0354).beta, 0.0310, 5e-4);
  EXPECT_NEAR(alpha_beta(0.1).alpha, 0.36, 5e-3);
  EXPECT_NEAR(alpha_beta(0.1).beta, 0.08, 5e-3);
  EXPECT_NEAR(alpha_beta(1.0).alpha, 0.75, 1e-12);
  EXPECT_NEAR(alpha_beta(1.0).beta, 0.50, 1e-12);
}

TEST(BallbeamAlphaBeta, TrackingIndexIsTsSquaredRootQOverR) {
  // The preset: Ts = 10 ms, Q = 0.5013 (m/s²)², R = (2 mm)² gives λ = 0.0354, α = 0.2335,
  // β = 0.0310 (seed 003 eq. 16), which Table 1 prints as α = 0.234, β = 0.031.
  const double l = tracking_index(0.01, 0.5013, 4e-6);
  EXPECT_NEAR(l, 1e-4 * std::sqrt(0.5013 / 4e-6), 1e-15);
  EXPECT_NEAR(l, 0.0354, 5e-5);
  EXPECT_NEAR(alpha_beta(l).alpha, 0.2335, 1e-4);
  EXPECT_NEAR(alpha_beta(l).beta, 0.0310, 1e-4);
  EXPECT_NEAR(alpha_beta(l).alpha, 0.234, 1e-3);
  EXPECT_NEAR(alpha_beta(l).beta, 0.031, 1e-3);
}

TEST(BallbeamAlphaBeta, ClosedFormEqualsDare) {
  for (double Ts : {0.001, 0.01, 0.05}) {
    for (double Q : {1e-3, 0.5, 100.0}) {
      for (double R : {1e-8, 4e-6, 1e-3}) {
        const double l = tracking_index(Ts, Q, R);
        auto ss = steady_gain_dare(Ts, Q, R);
        ASSERT_TRUE(ss.ok()) << ss.error();
        const AlphaBeta ab = alpha_beta(l);
        EXPECT_NEAR(ss->alpha, ab.alpha, 1e-8) << "Ts " << Ts << " Q " << Q << " R " << R;
        EXPECT_NEAR(ss->beta, ab.beta, 1e-8) << "Ts " << Ts << " Q " << Q << " R " << R;
        EXPECT_TRUE(kfw::testing::IsSymmetricPsd(ss->P_pred, 1e-15));
      }
    }
  }
}

TEST(BallbeamAlphaBeta, PaperTypoDoesNotMatchDare) {
  // With the printed λ = Ts² √(R/Q) the gain would be far from the DARE: the correction matters.
  const double Ts = 0.01, Q = 0.5, R = 4e-6;
  auto ss = steady_gain_dare(Ts, Q, R);
  ASSERT_TRUE(ss.ok());
  const AlphaBeta typo = alpha_beta(Ts * Ts * std::sqrt(R / Q));
  EXPECT_GT(std::abs(typo.alpha - ss->alpha), 0.1);
}

TEST(BallbeamAlphaBeta, DareEqualsLimitOfIteratedKf) {
  const double Ts = 0.01, Q = 0.5, R = 4e-6;
  const TrackModel m = track_model(Ts, Q);
  Gaussian<2> g{Vec<2>::Zero(), Covariance<2>::Identity()};
  Update<2, 1> u;
  for (int k = 0; k < 5000; ++k) {
    u = update_scalar(g, 0.0, m.H, R);
    g = predict(u.post, m.F, Vec<2>(Vec<2>::Zero()), m.Qd);
  }
  auto ss = steady_gain_dare(Ts, Q, R);
  ASSERT_TRUE(ss.ok());
  EXPECT_TRUE(kfw::testing::MatricesNear(u.K, ss->K, 1e-9));
  EXPECT_NEAR(u.K(1) * Ts, alpha_beta(tracking_index(Ts, Q, R)).beta, 1e-9);
}

TEST(BallbeamAlphaBeta, BadInputIsAnError) {
  EXPECT_FALSE(steady_gain_dare(0.0, 0.5, 4e-6).ok());
  EXPECT_NE(steady_gain_dare(0.0, 0.5, 4e-6).error().find("Ts"), std::string::npos);
  EXPECT_NE(steady_gain_dare(0.01, -1.0, 4e-6).error().find("Q"), std::string::npos);
  EXPECT_NE(steady_gain_dare(0.01, 0.5, std::nan("")).error().find("R"), std::string::npos);
  EXPECT_EQ(alpha_beta(-1.0).alpha, 0.0);
}

TEST(BallbeamAlphaBeta, GainCurveIsMonotone) {
  const GainCurve c = gain_curve(1e-4, 1e2, 50);
  ASSERT_EQ(c.lambda.size(), 50u);
  EXPECT_NEAR(c.lambda.front(), 1e-4, 1e-16);
  EXPECT_NEAR(c.lambda.back(), 1e2, 1e-10);
  for (std::size_t i = 1; i < c.lambda.size(); ++i) {
    EXPECT_GT(c.alpha[i], c.alpha[i - 1]);
    EXPECT_GT(c.beta[i], c.beta[i - 1]);
    EXPECT_LT(c.alpha[i], 1.0);  // α → 1, β → 2 as λ → ∞ (the filter trusts the sensor)
    EXPECT_LT(c.beta[i], 2.0);
  }
  EXPECT_TRUE(gain_curve(1.0, 0.5, 10).lambda.empty());
}

}  // namespace
}  // namespace kfw::ballbeam
