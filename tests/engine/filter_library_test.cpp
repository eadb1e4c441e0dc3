// The filter library's one measurement update (filter/measurement_update.h) and the UKF's moments
// (filter/ukf.h): the gate, the skip on an S that is not positive definite, angle wrapping of the
// innovation, log det S, the Joseph form against the C-form on the same numbers, and the circular
// mean of sigma points across ±π — each on numbers worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "common/matrix_matchers.h"
#include "filter/ekf.h"
#include "filter/kalman_filter.h"
#include "filter/measurement_update.h"
#include "filter/ukf.h"

namespace kfw {
namespace filter_library_test {

using testing::IsSymmetricPsd;
using testing::MatricesNear;

// The model engine's sizes: measurements of dynamic size, at most 4 components, no heap.
using D2 = FilterDims<2, Eigen::Dynamic, 4>;
using D3 = FilterDims<3, Eigen::Dynamic, 4>;

D2::Meas meas2(double a, double b) {
  D2::Meas y(2);
  y << a, b;
  return y;
}

// x = 0, P = I, z = x + v with R = I: S = 2 I, C = P Hᵀ = I.
struct UnitCase {
  Vec<2> x = Vec<2>::Zero();
  Covariance<2> P = Covariance<2>::Identity();
  D2::MeasJac H = D2::MeasJac::Identity(2, 2);
  D2::MeasCov R = D2::MeasCov::Identity(2, 2);
  D2::MeasCov S = 2.0 * D2::MeasCov::Identity(2, 2);
  D2::Cross C = D2::Cross::Identity(2, 2);
};

TEST(FilterLibrary, GateAboveTheThresholdKeepsYAndSAndChangesNothing) {
  UnitCase c;
  UpdateRules rules;
  rules.gate_nis = 4.0;  // NIS = (3² + 0²) / 2 = 4.5
  const auto gated = update(c.x, c.P, meas2(3.0, 0.0), c.S, c.C, rules, c.H, c.R);
  EXPECT_EQ(gated.status, UpdateStatus::kGated);
  EXPECT_DOUBLE_EQ(gated.nis, 4.5);
  EXPECT_DOUBLE_EQ(gated.y(0), 3.0);
  EXPECT_DOUBLE_EQ(gated.S(0, 0), 2.0);
  EXPECT_TRUE(std::isnan(gated.log_det_S));
  EXPECT_TRUE(MatricesNear(c.x, Vec<2>::Zero(), 0.0));
  EXPECT_TRUE(MatricesNear(c.P, Covariance<2>::Identity(), 0.0));

  rules.gate_nis = 5.0;  // the same measurement passes a wider gate: K = I/2
  const auto passed = update(c.x, c.P, meas2(3.0, 0.0), c.S, c.C, rules, c.H, c.R);
  EXPECT_EQ(passed.status, UpdateStatus::kUpdated);
  EXPECT_TRUE(MatricesNear(c.x, Vec<2>(1.5, 0.0), 1e-15));
  // Joseph: (I − K)(I − K)ᵀ + K Kᵀ = I/4 + I/4.
  EXPECT_TRUE(MatricesNear(c.P, (0.5 * Covariance<2>::Identity()).eval(), 1e-15));

  // The scalar path gates on the same NIS: y² / S = 9 / 2.
  Vec<2> x = Vec<2>::Zero();
  Covariance<2> P = Covariance<2>::Identity();
  const auto scalar = update(x, P, 3.0, 2.0, Vec<2>(1.0, 0.0), UpdateRules{{}, 4.0});
  EXPECT_EQ(scalar.status, UpdateStatus::kGated);
  EXPECT_DOUBLE_EQ(scalar.nis, 4.5);
  EXPECT_TRUE(MatricesNear(x, Vec<2>::Zero(), 0.0));
}

TEST(FilterLibrary, SNotPositiveDefiniteSkipsTheUpdate) {
  UnitCase c;
  D2::MeasCov S(2, 2);
  S << 1.0, 2.0, 2.0, 1.0;  // eigenvalues 3 and −1
  const auto indefinite = update(c.x, c.P, meas2(1.0, 1.0), S, c.C, UpdateRules{});
  EXPECT_EQ(indefinite.status, UpdateStatus::kSkipped);
  EXPECT_TRUE(std::isnan(indefinite.nis));
  EXPECT_TRUE(std::isnan(indefinite.log_det_S));
  S << 1.0, 0.0, 0.0, std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(update(c.x, c.P, meas2(1.0, 1.0), S, c.C, UpdateRules{}, c.H, c.R).status,
            UpdateStatus::kSkipped);
  EXPECT_TRUE(MatricesNear(c.x, Vec<2>::Zero(), 0.0));
  EXPECT_TRUE(MatricesNear(c.P, Covariance<2>::Identity(), 0.0));

  for (double s : {0.0, -1.0, std::numeric_limits<double>::infinity()}) {
    const auto u = update(c.x, c.P, 1.0, s, Vec<2>(1.0, 0.0), UpdateRules{});
    EXPECT_EQ(u.status, UpdateStatus::kSkipped) << "S = " << s;
    EXPECT_TRUE(std::isnan(u.nis));
  }
  EXPECT_TRUE(MatricesNear(c.x, Vec<2>::Zero(), 0.0));
}

TEST(FilterLibrary, AngleComponentsOfTheInnovationAreWrappedBeforeUse) {
  UnitCase c;
  const std::vector<Angle> angle = {Angle::kRad, Angle::kDeg};
  const double pi = std::numbers::pi;
  const auto u =
      update(c.x, c.P, meas2(1.5 * pi, 350.0), c.S, c.C, UpdateRules{angle, 0.0}, c.H, c.R);
  ASSERT_EQ(u.status, UpdateStatus::kUpdated);
  EXPECT_NEAR(u.y(0), -0.5 * pi, 1e-15);
  EXPECT_NEAR(u.y(1), -10.0, 1e-13);
  EXPECT_NEAR(u.nis, (0.25 * pi * pi + 100.0) / 2.0, 1e-12);
  EXPECT_TRUE(MatricesNear(c.x, Vec<2>(-0.25 * pi, -5.0), 1e-13));

  // The wrap itself: (−π, π] and (−180, 180], π and 180 included.
  EXPECT_DOUBLE_EQ(wrap(pi, Angle::kRad), pi);
  EXPECT_DOUBLE_EQ(wrap(-pi, Angle::kRad), pi);
  EXPECT_DOUBLE_EQ(wrap(-180.0, Angle::kDeg), 180.0);
  EXPECT_DOUBLE_EQ(wrap(540.0, Angle::kDeg), 180.0);
  EXPECT_DOUBLE_EQ(wrap(7.5, Angle::kNone), 7.5);
}

TEST(FilterLibrary, LogDetSIsTheLogOfTheDeterminant) {
  UnitCase c;
  D2::MeasCov R(2, 2);
  R << 3.0, 1.0, 1.0, 2.0;
  D2::MeasCov S(2, 2);
  D2::Cross C(2, 2);
  innovation_covariance(c.P, c.H, R, C, S);  // S = [4 1; 1 3], det 11
  const auto u = update(c.x, c.P, meas2(0.5, -0.5), S, C, UpdateRules{}, c.H, R);
  ASSERT_EQ(u.status, UpdateStatus::kUpdated);
  EXPECT_NEAR(u.log_det_S, std::log(11.0), 1e-14);
  // NIS = yᵀ S⁻¹ y with S⁻¹ = [3 −1; −1 4] / 11: (0.75 + 0.5 + 1) / 11.
  EXPECT_NEAR(u.nis, 2.25 / 11.0, 1e-15);

  Vec<2> x = Vec<2>::Zero();
  Covariance<2> P = Covariance<2>::Identity();
  const auto scalar = update(x, P, 0.5, 2.5, Vec<2>(1.0, 0.0), UpdateRules{});
  EXPECT_EQ(scalar.log_det_S, std::log(2.5));
  EXPECT_EQ(scalar.nis, 0.25 / 2.5);
}

// A 3-state prior and a 2-component measurement of x₀ and x₁ + x₂.
struct JosephCase {
  Vec<3> x{1.0, -2.0, 0.5};
  Covariance<3> P = (Covariance<3>() << 4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0).finished();
  D3::MeasJac H = (D3::MeasJac(2, 3) << 1.0, 0.0, 0.0, 0.0, 1.0, 1.0).finished();
  D3::MeasCov R = (D3::MeasCov(2, 2) << 0.5, 0.0, 0.0, 0.8).finished();
  D3::Meas y = (D3::Meas(2) << 0.3, -0.7).finished();
};

TEST(FilterLibrary, JosephFormEqualsTheCFormOnTheSameNumbers) {
  JosephCase j;
  D3::Cross C(3, 2);
  D3::MeasCov S(2, 2);
  innovation_covariance(j.P, j.H, j.R, C, S);
  Vec<3> xj = j.x, xc = j.x;
  Covariance<3> Pj = j.P, Pc = j.P;
  const auto uj = update(xj, Pj, j.y, S, C, UpdateRules{}, j.H, j.R);
  const auto uc = update(xc, Pc, j.y, S, C, UpdateRules{});
  ASSERT_TRUE(uj.updated() && uc.updated());
  // The same gain and state; the covariances agree to rounding and with the textbook P − K H P.
  const Mat<3, 2> K = C * S.inverse();
  EXPECT_TRUE(MatricesNear(uj.K, K, 1e-15));
  EXPECT_TRUE(MatricesNear(uj.K, uc.K, 0.0));
  EXPECT_TRUE(MatricesNear(xj, xc, 0.0));
  EXPECT_TRUE(MatricesNear(xj, (j.x + K * j.y).eval(), 1e-15));
  const Covariance<3> textbook = j.P - K * j.H * j.P;
  EXPECT_TRUE(MatricesNear(Pj, Pc, 1e-14));
  EXPECT_TRUE(MatricesNear(Pj, textbook, 1e-14));
  EXPECT_TRUE(IsSymmetricPsd(Pj, 0.0));
  EXPECT_TRUE(IsSymmetricPsd(Pc, 0.0));
  // By hand: C = [4 1.5; 1 3.2; 0.5 2.2], S = [4.5 1.5; 1.5 6.2] (det 25.65), so
  // P₀₀ = 4 − (4² · 6.2 − 2 · 4 · 1.5 · 1.5 + 1.5² · 4.5) / 25.65.
  EXPECT_NEAR(Pj(0, 0), 4.0 - 91.325 / 25.65, 1e-14);

  // The scalar path (no LLT) equals the matrix path on the first component.
  Vec<3> xs = j.x, xm = j.x;
  Covariance<3> Ps = j.P, Pm = j.P;
  const Vec<3> C0 = C.col(0);
  const auto us = update(xs, Ps, j.y(0), S(0, 0), C0, UpdateRules{});
  const FilterDims<3, 1>::MeasJac H0 = j.H.row(0);
  const auto um = update(xm, Pm, Vec<1>(j.y(0)), Mat<1, 1>(S(0, 0)), C0, UpdateRules{}, H0,
                         Mat<1, 1>(j.R(0, 0)));
  EXPECT_TRUE(MatricesNear(xs, xm, 1e-15));
  EXPECT_TRUE(MatricesNear(Ps, Pm, 1e-14));
  EXPECT_NEAR(us.nis, um.nis, 1e-15);
  EXPECT_NEAR(us.nis, 0.09 / 4.5, 1e-15);
}

TEST(FilterLibrary, EkfOnALinearMeasurementIsTheKalmanFilter) {
  JosephCase j;
  const Gaussian<3> prior{j.x, j.P};
  const Mat<2, 3> H = j.H;
  const Covariance<2> R = j.R;
  const Vec<2> z(1.1, -1.0);
  const auto kf = update(prior, z, H, R);
  const auto ekf = ekf_update(prior, z, Vec<2>(H * j.x), H, R);
  ASSERT_TRUE(kf.ok && ekf.ok);
  EXPECT_TRUE(MatricesNear(ekf.post.x, kf.post.x, 0.0));
  EXPECT_TRUE(MatricesNear(ekf.post.P, kf.post.P, 0.0));
  EXPECT_TRUE(MatricesNear(kf.innovation, Vec<2>(0.1, 0.5), 1e-15));

  // The EKF's gate reaches the functional update too: a 100σ innovation is kept out.
  const std::vector<Angle> none(2, Angle::kNone);
  const auto gated = ekf_update(prior, Vec<2>(z + Vec<2>(100.0, 0.0)), Vec<2>(H * j.x), H, R,
                                UpdateRules{none, 9.21});
  EXPECT_EQ(gated.status, UpdateStatus::kGated);
  EXPECT_FALSE(gated.ok);
  EXPECT_TRUE(MatricesNear(gated.post.x, j.x, 0.0));
}

TEST(FilterLibrary, UkfMeanOfSigmaPointsAcrossPlusMinusPiIsCircular) {
  // n = 1, α = 1, β = 0, κ = 2: λ = 2, n + λ = 3, W0 = 2/3, Wi = 1/6.
  const UkfWeights w = UkfWeights::scaled(1, 1.0, 0.0, 2.0);
  EXPECT_DOUBLE_EQ(w.c, 3.0);
  EXPECT_DOUBLE_EQ(w.m0, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(w.i, 1.0 / 6.0);
  // An angle at 3.1 rad with σ = 0.1: the sigma points 3.1 ± √0.03 straddle +π.
  const Vec<1> x0(3.1);
  const Covariance<1> P0(0.01);
  Mat<1, 3> X;
  ASSERT_TRUE(sigma_points<1>(x0, P0, w, X));
  EXPECT_NEAR(X(0, 1), 3.1 + std::sqrt(0.03), 1e-15);
  // f(x) = x, as a model that wraps its angle state returns it: one point lands near −π.
  Mat<1, 3> Y;
  for (int j = 0; j < 3; ++j)
    Y(0, j) = wrap(X(0, j), Angle::kRad);
  EXPECT_LT(Y(0, 1), -3.0);

  const std::vector<Angle> rad = {Angle::kRad};
  Vec<1> x;
  Covariance<1> P;
  unscented_predict(Y, w, rad, Covariance<1>(Covariance<1>::Zero()), x, P);
  EXPECT_NEAR(x(0), 3.1, 1e-14);      // the identity through sigma points keeps the mean ...
  EXPECT_NEAR(P(0, 0), 0.01, 1e-15);  // ... and the variance
  // The plain weighted mean would fall a sixth of a turn short.
  const std::vector<Angle> plain = {Angle::kNone};
  Vec<1> xp;
  sigma_mean(Y, w, plain, xp);
  EXPECT_NEAR(xp(0), 3.1 - std::numbers::pi / 3.0, 1e-14);
}

TEST(FilterLibrary, UkfMomentsOfALinearMeasurementAreHPHtPlusRAndPHt) {
  JosephCase j;
  const UkfWeights w = UkfWeights::scaled(3, 0.5, 2.0, 0.0);
  Mat<3, 7> X;
  ASSERT_TRUE(sigma_points<3>(j.x, j.P, w, X));
  const MatX Z = j.H * X;
  const std::vector<Angle> none3(3, Angle::kNone), none2(2, Angle::kNone);
  const auto m = unscented_measurement<3, Eigen::Dynamic, 4>(X, j.x, Z, w, none3, none2, j.R);
  EXPECT_TRUE(MatricesNear(m.zhat, (j.H * j.x).eval(), 1e-14));
  EXPECT_TRUE(MatricesNear(m.S, (j.H * j.P * j.H.transpose() + j.R).eval(), 1e-13));
  EXPECT_TRUE(MatricesNear(m.C, (j.P * j.H.transpose()).eval(), 1e-13));
}

}  // namespace filter_library_test
}  // namespace kfw
