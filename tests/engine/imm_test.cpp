#include "filter/imm.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/matrix_matchers.h"
#include "filter/kalman_filter.h"

namespace kfw {
namespace {

using testing::IsSymmetricPsd;
using testing::MatricesNear;

ImmModel<2, 1> cv_model(double T, double q, double r) {
  ImmModel<2, 1> m;
  m.F << 1, T, 0, 1;
  m.Bu.setZero();
  m.Q << T * T * T / 3, T * T / 2, T * T / 2, T;
  m.Q *= q;
  m.H << 1, 0;
  m.R << r;
  return m;
}

Gaussian<4> random_gaussian(std::mt19937_64& rng, double scale) {
  std::normal_distribution<double> n(0.0, 1.0);
  Gaussian<4> g;
  Mat<4> L;
  for (int i = 0; i < 4; ++i) {
    g.x(i) = scale * n(rng);
    for (int j = 0; j < 4; ++j)
      L(i, j) = n(rng);
  }
  g.P = L * L.transpose() + Mat<4>::Identity();
  return g;
}

TEST(Imm, OneModeEqualsPlainKalmanFilter) {
  const auto m = cv_model(0.1, 2.0, 0.5);
  auto chain = MarkovChain::uniform(1, 0.9);
  ASSERT_TRUE(chain.ok());
  Gaussian<2> kf{Vec<2>(1.0, 0.0), Mat<2>::Identity() * 10.0};
  ImmState<2> s;
  s.modes = {kf};
  s.log_mu = VecX::Zero(1);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    const Vec<1> z(std::sin(0.05 * k) * 5 + noise(rng));
    kf = update(predict(kf, m.F, m.Bu, m.Q), z, m.H, m.R).post;
    const auto step = imm_step<2, 1>(s, *chain, {m}, {z});
    ASSERT_TRUE(step.ok);
    s = step.state;
    ASSERT_TRUE(MatricesNear(step.combined.x, kf.x, 1e-12)) << "step " << k;
    ASSERT_TRUE(MatricesNear(step.combined.P, kf.P, 1e-12)) << "step " << k;
    EXPECT_NEAR(s.log_mu(0), 0.0, 1e-15);
  }
}

TEST(Imm, IdenticalModesEqualPlainKalmanFilter) {
  // r copies of the same model: mixing and combination must not change the KF estimate.
  const auto m = cv_model(0.2, 1.0, 0.3);
  auto chain = MarkovChain::uniform(5, 0.8);
  ASSERT_TRUE(chain.ok());
  Gaussian<2> kf{Vec<2>(0.0, 1.0), Mat<2>::Identity() * 4.0};
  ImmState<2> s;
  s.modes.assign(5, kf);
  s.log_mu = VecX::Constant(5, -std::log(5.0));
  for (int k = 0; k < 50; ++k) {
    const Vec<1> z(0.3 * k);
    kf = update(predict(kf, m.F, m.Bu, m.Q), z, m.H, m.R).post;
    const auto step = imm_step<2, 1>(s, *chain, {m}, {z});
    s = step.state;
    ASSERT_TRUE(MatricesNear(step.combined.x, kf.x, 1e-10));
    ASSERT_TRUE(MatricesNear(step.combined.P, kf.P, 1e-10));
  }
}

TEST(Imm, UniformMixingEqualsTable2BruteForce) {
  // The O(r) mixing of the uniform chain against Table 2 written out with the dense matrix:
  // μ^{ij} = p^{ij} μ^i / c̄^j, x^{0j} = Σ μ^{ij} x^i, P^{0j} = Σ μ^{ij} (P^i + d d^T).
  std::mt19937_64 rng(3);
  const int r = 6;
  std::vector<Gaussian<4>> g;
  for (int i = 0; i < r; ++i)
    g.push_back(random_gaussian(rng, 1e4));  // large states
  VecX mu(r);
  mu << 0.5, 0.2, 0.1, 0.1, 0.07, 0.03;
  const VecX log_mu = mu.array().log();
  auto uni = MarkovChain::uniform(r, 0.9);
  auto den = MarkovChain::dense(uni->matrix());
  ASSERT_TRUE(uni.ok() && den.ok());
  std::vector<Gaussian<4>> a, b;
  const ImmMixing wu = imm_mixing(*uni, log_mu), wd = imm_mixing(*den, log_mu);
  imm_mix(wu, g, a);
  imm_mix(wd, g, b);
  const MatX p = uni->matrix();
  for (int j = 0; j < r; ++j) {
    double c = 0.0;
    for (int i = 0; i < r; ++i)
      c += p(i, j) * mu(i);
    EXPECT_NEAR(std::exp(wu.log_c_bar(j)), c, 1e-15);
    Vec<4> x = Vec<4>::Zero();
    for (int i = 0; i < r; ++i)
      x += p(i, j) * mu(i) / c * g[i].x;
    Mat<4> P = Mat<4>::Zero();
    for (int i = 0; i < r; ++i) {
      const Vec<4> d = g[i].x - x;
      P += p(i, j) * mu(i) / c * (g[i].P + d * d.transpose());
    }
    EXPECT_TRUE(MatricesNear(a[j].x, x, 1e-8));
    EXPECT_TRUE(MatricesNear(a[j].P, P, 1e-6 * P.norm()));
    EXPECT_TRUE(MatricesNear(b[j].x, x, 1e-8));
    EXPECT_TRUE(MatricesNear(b[j].P, P, 1e-6 * P.norm()));
    EXPECT_TRUE(IsSymmetricPsd(a[j].P, 1e-6));
  }
}

TEST(Imm, LogDomainMatchesLinearWhenNothingUnderflows) {
  VecX log_c_bar(3), ll(3);
  log_c_bar << std::log(0.2), std::log(0.3), std::log(0.5);
  ll << -1.0, -2.0, -0.5;
  const auto p = imm_update_probabilities(log_c_bar, ll);
  ASSERT_TRUE(p.ok);
  double c = 0.0;
  for (int j = 0; j < 3; ++j)
    c += std::exp(ll(j)) * std::exp(log_c_bar(j));
  for (int j = 0; j < 3; ++j) {
    EXPECT_NEAR(std::exp(p.log_mu(j)), std::exp(ll(j)) * std::exp(log_c_bar(j)) / c, 1e-15);
  }
  EXPECT_NEAR(p.log_c, std::log(c), 1e-14);
}

TEST(Imm, UnderflowingLikelihoodGivesZeroNotNaN) {
  // exp(−2000) underflows to 0 in double: linear-domain IMM would divide 0 by 0.
  VecX log_c_bar = VecX::Constant(3, std::log(1.0 / 3));
  VecX ll(3);
  ll << -2000.0, -2005.0, -3000.0;
  auto p = imm_update_probabilities(log_c_bar, ll);
  ASSERT_TRUE(p.ok);
  EXPECT_TRUE(p.log_mu.allFinite());
  EXPECT_NEAR(std::exp(p.log_mu(0)), 1.0 / (1.0 + std::exp(-5.0)), 1e-12);
  EXPECT_EQ(std::exp(p.log_mu(2)), 0.0);
  // A NaN or −∞ likelihood (S not positive definite) gives that mode probability 0.
  ll << -1.0, std::nan(""), -std::numeric_limits<double>::infinity();
  p = imm_update_probabilities(log_c_bar, ll);
  ASSERT_TRUE(p.ok);
  EXPECT_NEAR(std::exp(p.log_mu(0)), 1.0, 1e-15);
  EXPECT_EQ(std::exp(p.log_mu(1)), 0.0);
  EXPECT_EQ(std::exp(p.log_mu(2)), 0.0);
  // No mode usable: keep the prediction and say so, never NaN.
  ll.setConstant(-std::numeric_limits<double>::infinity());
  p = imm_update_probabilities(log_c_bar, ll);
  EXPECT_FALSE(p.ok);
  EXPECT_TRUE(p.log_mu.allFinite());
  EXPECT_NEAR(p.log_mu.array().exp().sum(), 1.0, 1e-15);
}

TEST(Imm, DeadModeIsRevivedByTheChainWithoutNaN) {
  // After a mode's probability underflows to exactly 0, the next mixing must still be finite.
  const auto m = cv_model(0.1, 1.0, 1e-4);
  auto chain = MarkovChain::uniform(2, 0.95);
  ImmState<2> s;
  s.modes = {Gaussian<2>{Vec<2>(0, 0), Mat<2>::Identity()},
             Gaussian<2>{Vec<2>(1e3, 0), Mat<2>::Identity()}};
  s.log_mu.resize(2);
  s.log_mu << 0.0, -std::numeric_limits<double>::infinity();
  for (int k = 0; k < 5; ++k) {
    const auto step = imm_step<2, 1>(s, *chain, {m}, {Vec<1>(0.0)});
    ASSERT_TRUE(step.combined.x.allFinite());
    ASSERT_TRUE(step.combined.P.allFinite());
    ASSERT_TRUE(step.state.log_mu.array().isNaN().count() == 0);
    EXPECT_NEAR(step.state.log_mu.array().exp().sum(), 1.0, 1e-12);
    s = step.state;
  }
}

TEST(Imm, PicksTheModeThatExplainsTheData) {
  // Two constant-position models with different offsets in H x + b, through per-mode z.
  ImmModel<1, 1> m;
  m.F << 1;
  m.Bu << 0;
  m.Q << 1e-4;
  m.H << 1;
  m.R << 0.01;
  auto chain = MarkovChain::uniform(2, 0.99);
  ImmState<1> s;
  s.modes.assign(2, Gaussian<1>{Vec<1>(0.0), Mat<1>::Constant(1.0)});
  s.log_mu = VecX::Constant(2, std::log(0.5));
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n(0.0, 0.1);
  for (int k = 0; k < 100; ++k) {
    const double z = 2.0 + 0.01 * k + n(rng);  // a slow ramp: only the ramp-corrected mode fits
    const auto step = imm_step<1, 1>(s, *chain, {m}, {Vec<1>(z), Vec<1>(z - 0.01 * k)});
    s = step.state;
  }
  EXPECT_GT(std::exp(s.log_mu(1)), 0.9);
}

TEST(MarkovChain, RejectsBadStayAndRows) {
  EXPECT_FALSE(MarkovChain::uniform(3, 0.0).ok());
  EXPECT_FALSE(MarkovChain::uniform(3, 1.2).ok());
  EXPECT_FALSE(MarkovChain::uniform(0, 0.9).ok());
  EXPECT_TRUE(MarkovChain::uniform(3, 1.0).ok());
  auto bad = MarkovChain::uniform(3, -0.1);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("markov.stay"), std::string::npos);
  MatX p(2, 2);
  p << 0.9, 0.2, 0.1, 0.9;
  EXPECT_FALSE(MarkovChain::dense(p).ok());
  const MatX u = MarkovChain::uniform(4, 0.7)->matrix();
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(u.row(i).sum(), 1.0, 1e-15);
}

TEST(Imm, LogGaussianMatchesDensity) {
  Covariance<2> S;
  S << 2.0, 0.3, 0.3, 1.0;
  const Vec<2> y(0.4, -1.1);
  const double direct = std::exp(-0.5 * y.dot(S.inverse() * y)) /
                        (2.0 * std::numbers::pi * std::sqrt(S.determinant()));
  EXPECT_NEAR(log_gaussian<2>(y, S), std::log(direct), 1e-13);
  S << 1, 2, 2, 1;  // indefinite
  EXPECT_EQ(log_gaussian<2>(y, S), -std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace kfw
