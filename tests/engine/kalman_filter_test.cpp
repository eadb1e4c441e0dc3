// Identities of the functional KF (filter/kalman_filter.h) that cannot be faked.
#include "filter/kalman_filter.h"

#include <gtest/gtest.h>

#include <random>

#include "common/matrix_matchers.h"
#include "filter/dare.h"

namespace kfw {
namespace {

using testing::IsSymmetricPsd;
using testing::MatricesNear;

struct CvModel {
  Mat<2> F;
  Covariance<2> Q;
  Mat<1, 2> H;
  Covariance<1> R;
};

CvModel cv(double Ts, double q, double r) {
  CvModel m;
  m.F << 1, Ts, 0, 1;
  const Vec<2> G(Ts * Ts / 2, Ts);
  m.Q = G * q * G.transpose();
  m.H << 1, 0;
  m.R << r;
  return m;
}

TEST(KalmanFilter, PredictMatchesTextbook) {
  Gaussian<2> g{Vec<2>(1.0, 2.0), (Covariance<2>() << 2, 0.5, 0.5, 1).finished()};
  const auto m = cv(0.1, 3.0, 1.0);
  const auto p = predict(g, m.F, Vec<2>(0.01, 0.0), m.Q);
  EXPECT_TRUE(MatricesNear(p.x, Vec<2>(1.0 + 0.2 + 0.01, 2.0), 1e-15));
  EXPECT_TRUE(MatricesNear(p.P, (m.F * g.P * m.F.transpose() + m.Q).eval(), 1e-15));
}

TEST(KalmanFilter, JosephUpdateEqualsShortFormAndStaysPsd) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  const auto m = cv(0.05, 10.0, 0.3);
  Gaussian<2> g{Vec<2>::Zero(), Covariance<2>::Identity() * 100.0};
  for (int k = 0; k < 2000; ++k) {
    g = predict(g, m.F, Vec<2>(0, 0), m.Q);
    const Vec<1> z(n(rng));
    const auto u = update(g, z, m.H, m.R);
    ASSERT_TRUE(u.ok);
    const Covariance<2> short_form = (Covariance<2>::Identity() - u.K * m.H) * g.P;
    EXPECT_TRUE(MatricesNear(u.post.P, short_form, 1e-9 * (1.0 + g.P.norm())));
    EXPECT_TRUE(IsSymmetricPsd(u.post.P, 0.0));
    const auto us = update_scalar(g, z(0), m.H, m.R(0, 0));
    EXPECT_TRUE(MatricesNear(us.post.P, u.post.P, 1e-9));
    EXPECT_NEAR(us.nis, u.nis, 1e-9);
    g = u.post;
  }
}

TEST(KalmanFilter, NisIsInnovationOverS) {
  const auto m = cv(0.1, 1.0, 2.0);
  Gaussian<2> g{Vec<2>(0.5, 0.0), Covariance<2>::Identity()};
  const auto u = update(g, Vec<1>(1.5), m.H, m.R);
  EXPECT_DOUBLE_EQ(u.innovation(0), 1.0);
  EXPECT_DOUBLE_EQ(u.S(0, 0), 3.0);
  EXPECT_NEAR(u.nis, 1.0 / 3.0, 1e-15);
}

TEST(KalmanFilter, SingularInnovationCovarianceSkipsUpdate) {
  const auto m = cv(0.1, 1.0, 1.0);
  Gaussian<2> g{Vec<2>(1.0, 2.0), Covariance<2>::Zero()};
  const auto u = update(g, Vec<1>(3.0), m.H, Covariance<1>(Covariance<1>::Zero()));
  EXPECT_FALSE(u.ok);
  EXPECT_TRUE(MatricesNear(u.post.x, g.x, 0.0));
  const auto us = update_scalar(g, 3.0, m.H, 0.0);
  EXPECT_FALSE(us.ok);
  EXPECT_TRUE(std::isnan(us.nis));
}

TEST(KalmanFilter, IteratedGainConvergesToDareGain) {
  const auto m = cv(0.02, 5.0, 0.5);
  Gaussian<2> g{Vec<2>::Zero(), Covariance<2>::Identity() * 10.0};
  Gain<2, 1> K;
  for (int k = 0; k < 20000; ++k) {
    g = predict(g, m.F, Vec<2>(0, 0), m.Q);
    const auto u = update(g, Vec<1>(0.0), m.H, m.R);
    K = u.K;
    g = u.post;
  }
  auto ss = solve_dare(m.F, m.H, m.Q, m.R);
  ASSERT_TRUE(ss.ok()) << ss.error();
  EXPECT_TRUE(MatricesNear(K, ss->K, 1e-9));
}

TEST(KalmanFilter, DynamicSizeWorksLikeFixed) {
  const auto m = cv(0.1, 1.0, 2.0);
  Gaussian<Eigen::Dynamic> gd{VecX::Zero(2), MatX::Identity(2, 2)};
  Gaussian<2> gf{Vec<2>::Zero(), Covariance<2>::Identity()};
  const MatX F = m.F, Q = m.Q, H = m.H, R = m.R;
  gd = predict<Eigen::Dynamic>(gd, F, VecX::Zero(2), Q);
  gf = predict(gf, m.F, Vec<2>(0, 0), m.Q);
  VecX z(1);
  z << 0.7;
  const auto ud = update<Eigen::Dynamic, Eigen::Dynamic>(gd, z, H, R);
  const auto uf = update(gf, Vec<1>(0.7), m.H, m.R);
  EXPECT_TRUE(MatricesNear(ud.post.P, uf.post.P, 1e-15));
  EXPECT_TRUE(MatricesNear(ud.post.x, uf.post.x, 1e-15));
}

}  // namespace
}  // namespace kfw
