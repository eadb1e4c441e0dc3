// Seed 003 ball tracking filter: missing samples output the prediction; both filters keep a
// symmetric PSD covariance; the steady filter carries the DARE covariance; the u^c input is exact.
#include "oracles/ballbeam/ball_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/matrix_matchers.h"

namespace kfw::ballbeam {
namespace {

using kfw::testing::IsSymmetricPsd;
using kfw::testing::MatricesNear;

BallTracker make(FilterKind kind, double Ts = 0.01, double Q = 0.5, double R = 4e-6) {
  TrackerParams p;
  p.Ts_s = Ts;
  p.Q = Q;
  p.R = R;
  p.kind = kind;
  auto t = BallTracker::make(p);
  EXPECT_TRUE(t.ok());
  return *t;
}

class BallTrackerBoth : public ::testing::TestWithParam<FilterKind> {};

TEST_P(BallTrackerBoth, MissingSampleOutputsThePrediction) {
  const BallTracker t = make(GetParam());
  Gaussian<2> g = t.initial(0.05);
  g.x(1) = 0.2;
  const Gaussian<2> prior = t.predict(g, 0.3);
  const auto s = t.update(prior, 123.0, /*missing=*/true);  // the spike is ignored
  EXPECT_FALSE(s.updated);
  EXPECT_TRUE(MatricesNear(s.out.x, prior.x, 0.0));
  EXPECT_TRUE(MatricesNear(s.out.P, prior.P, 0.0));
  EXPECT_TRUE(std::isnan(s.innovation));
  // x̄ = F x̂ + G^c u^c (eq. 15).
  EXPECT_NEAR(prior.x(0), 0.05 + 0.01 * 0.2 + 0.5 * 1e-4 * 0.3, 1e-15);
  EXPECT_NEAR(prior.x(1), 0.2 + 0.01 * 0.3, 1e-15);
  // NaN readings are missing too.
  EXPECT_FALSE(t.update(prior, std::nan(""), false).updated);
}

TEST_P(BallTrackerBoth, CovarianceStaysSymmetricPsdThroughMissingData) {
  const BallTracker t = make(GetParam());
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 0.002);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Gaussian<2> g = t.initial(0.0);
  for (int k = 0; k < 3000; ++k) {
    const auto s = t.update(k ? t.predict(g, 0.0) : g, n(rng), u(rng) < 0.2);
    g = s.out;
    ASSERT_TRUE(IsSymmetricPsd(g.P, 1e-14)) << "step " << k;
  }
}

TEST_P(BallTrackerBoth, ControlInputIsTrackedWithoutBias) {
  // A ball under constant acceleration a3 θ read without noise: with u^c in the model the
  // estimate converges to the truth exactly.
  const BallTracker t = make(GetParam());
  const double Ts = 0.01, acc = 0.48;
  Gaussian<2> g = t.initial(0.0);
  for (int k = 0; k < 4000; ++k) {
    const double tk = k * Ts;
    g = t.update(k ? t.predict(g, acc) : g, 0.5 * acc * tk * tk, false).out;
  }
  const double tk = 3999 * Ts;
  EXPECT_NEAR(g.x(0), 0.5 * acc * tk * tk, 1e-9);
  EXPECT_NEAR(g.x(1), acc * tk, 1e-7);
}

INSTANTIATE_TEST_SUITE_P(Kinds, BallTrackerBoth,
                         ::testing::Values(FilterKind::kKalman, FilterKind::kSteady));

TEST(BallTracker, SteadyGainIsClosedFormAndItsCovarianceIsTheDare) {
  const BallTracker t = make(FilterKind::kSteady);
  auto ss = steady_gain_dare(0.01, 0.5, 4e-6);
  ASSERT_TRUE(ss.ok());
  Gaussian<2> g = t.initial(0.0);
  BallTracker::Step s;
  for (int k = 0; k < 3000; ++k) {
    s = t.update(k ? t.predict(g, 0.0) : g, 0.0, false);
    g = s.out;
  }
  EXPECT_NEAR(s.K1, ss->alpha, 1e-9);
  EXPECT_NEAR(s.K2 * 0.01, ss->beta, 1e-9);
  // With the optimal gain fixed, the Joseph recursion converges to the DARE's P_post.
  EXPECT_TRUE(MatricesNear(g.P, ss->P_post, 1e-12 + 1e-8 * ss->P_post.norm()));
}

TEST(BallTracker, KalmanGainConvergesToSteadyGain) {
  const BallTracker kf = make(FilterKind::kKalman);
  Gaussian<2> g = kf.initial(0.0);
  BallTracker::Step s;
  for (int k = 0; k < 3000; ++k) {
    s = kf.update(k ? kf.predict(g, 0.0) : g, 0.0, false);
    g = s.out;
  }
  EXPECT_NEAR(s.K1, kf.gains().alpha, 1e-9);
  EXPECT_NEAR(s.K2 * 0.01, kf.gains().beta, 1e-9);
}

TEST(BallTracker, BadParametersAreErrorsNamingTheKey) {
  TrackerParams p;
  p.Ts_s = 0.0;
  auto a = BallTracker::make(p);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().find("Ts"), std::string::npos);
  p = TrackerParams{};
  p.Q = -1.0;
  EXPECT_NE(BallTracker::make(p).error().find("Q"), std::string::npos);
  p = TrackerParams{};
  p.R = 0.0;
  EXPECT_NE(BallTracker::make(p).error().find("R"), std::string::npos);
}

}  // namespace
}  // namespace kfw::ballbeam
