// Seed 000's oracle: closed-form steady state vs the DARE, the model matrices, the simulator and
// the scalar filter.
#include "oracles/helicopter/helicopter_model.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/matrix_matchers.h"

namespace kfw::helicopter {
namespace {

struct Row {
  double beta, k1, p11;
};

// Seed 000 eq. 11, the table of docs/reproductions.md (checked against the DARE to 4 digits).
class ClosedForm : public ::testing::TestWithParam<Row> {};

TEST_P(ClosedForm, MatchesSpecTable) {
  const Row r = GetParam();
  EXPECT_NEAR(k1_closed_form(r.beta), r.k1, 5e-5);
  EXPECT_NEAR(p11_over_R(r.beta), r.p11, 5e-5);
}

TEST_P(ClosedForm, EqualsDareOfTheMStepModel) {
  const Row r = GetParam();
  // Pick Ts, N_θ and m, then N_ω so that β = m Ts² N_ω / N_θ.
  for (int m : {1, 5, 25, 100}) {
    const double Ts = 0.02, Nt = 1.9;
    const double Nw = r.beta * Nt / (m * Ts * Ts);
    ASSERT_NEAR(beta(m, Ts, Nw, Nt), r.beta, 1e-12);
    auto g = steady_gain_dare(m, Ts, 0.0, Nw, Nt);
    ASSERT_TRUE(g.ok()) << g.error();
    EXPECT_NEAR(g->k1, k1_closed_form(r.beta), 1e-8) << "m = " << m;
    EXPECT_NEAR(g->k2, 0.0, 1e-6) << "m = " << m;
    EXPECT_NEAR(g->p11_pred / Nt, p11_over_R(r.beta), 1e-7) << "m = " << m;
  }
}

INSTANTIATE_TEST_SUITE_P(SpecTable, ClosedForm,
                         ::testing::Values(Row{0.01, 0.0951, 0.1051}, Row{0.05, 0.2000, 0.2500},
                                           Row{0.27, 0.4019, 0.6719}, Row{1.06, 0.6280, 1.6880}));

TEST(HelicopterModel, ConstantBiasMatrices) {
  const Model md = model(0.02, 0.0);
  EXPECT_TRUE(testing::MatricesNear(md.F, (Mat<2>() << 1, -0.02, 0, 1).finished(), 0));
  EXPECT_TRUE(testing::MatricesNear(md.B, Vec<2>(0.02, 0), 0));
  EXPECT_TRUE(testing::MatricesNear(md.G, Vec<2>(-0.02, 0), 0));
  EXPECT_TRUE(testing::MatricesNear(md.H, (Mat<1, 2>() << 1, 0).finished(), 0));
}

// Seed 000 eq. 12: F = [[1, -Ts], [0, 1-γ]], B = [Ts, γ]^T.
TEST(HelicopterModel, SlowlyVaryingBiasMatrices) {
  const Model md = model(0.02, 0.006);
  EXPECT_TRUE(testing::MatricesNear(md.F, (Mat<2>() << 1, -0.02, 0, 0.994).finished(), 1e-15));
  EXPECT_TRUE(testing::MatricesNear(md.B, Vec<2>(0.02, 0.006), 0));
  // The bias low-passes the measured rate: a constant ω_m = c drives b to c.
  Vec<2> x(0, 0);
  for (int k = 0; k < 20000; ++k)
    x = md.F * x + md.B * 3.0;
  EXPECT_NEAR(x(1), 3.0, 1e-9);
}

TEST(HelicopterModel, DareWithGammaHasGainBelowOne) {
  auto g = steady_gain_dare(1, 0.02, 0.006, 67.0, 1.96);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_GT(g->k1, 0.0);
  EXPECT_LT(g->k1, 1.0);
  EXPECT_FALSE(steady_gain_dare(0, 0.02, 0.0, 1, 1).ok());
}

TEST(HelicopterModel, GainCurveIsMonotoneAndLogSpaced) {
  const auto c = gain_curve(1e-4, 1e2, 61);
  ASSERT_EQ(c.beta.size(), 61u);
  EXPECT_NEAR(c.beta.front(), 1e-4, 1e-16);
  EXPECT_NEAR(c.beta.back(), 1e2, 1e-10);
  for (std::size_t i = 1; i < c.beta.size(); ++i) {
    EXPECT_GT(c.k1[i], c.k1[i - 1]);
    EXPECT_GT(c.p11_over_R[i], c.p11_over_R[i - 1]);
  }
}

}  // namespace
}  // namespace kfw::helicopter

#include "filter/kalman_filter.h"
#include "oracles/helicopter/helicopter_sim.h"
#include "oracles/helicopter/indirect_kf.h"

namespace kfw::helicopter {
namespace {

TEST(HelicopterSim, SameSeedSameDataOtherSeedOtherData) {
  SimParams p;
  p.duration_s = 5;
  const auto a = simulate(p), b = simulate(p);
  p.seed = 2;
  const auto c = simulate(p);
  EXPECT_EQ(a.columns, b.columns);
  EXPECT_NE(a.col("gyro"), c.col("gyro"));
  EXPECT_EQ(a.rows(), 251u);
}

TEST(HelicopterSim, NoiseLevelsAreWhatWasAsked) {
  SimParams p;
  p.duration_s = 400;
  const auto d = simulate(p);
  double se = 0;
  const auto& angle = d.col("angle");
  const auto& truth = d.col("truth");
  for (std::size_t i = 0; i < d.rows(); ++i)
    se += (angle[i] - truth[i]) * (angle[i] - truth[i]);
  EXPECT_NEAR(std::sqrt(se / d.rows()), p.sigma_angle, 0.03 * p.sigma_angle);
}

// The scalar runner is the textbook recursion: the same numbers as predict()/update() on the
// model matrices, for both bias models and a multi-rate schedule.
TEST(IndirectKf, EqualsGenericKalmanFilterOnTheModel) {
  SimParams sp;
  sp.duration_s = 20;
  sp.angle_dropout = 0.2;
  const auto d = simulate(sp);
  for (double gamma : {0.0, 0.006}) {
    FilterParams fp;
    fp.N_omega = 50;
    fp.N_theta = 2;
    fp.m = 3;
    fp.gamma = gamma;
    const auto r = run_indirect_kf(d.col("t"), d.col("gyro"), d.col("angle"), fp);
    const double a0 = d.col("angle")[0];
    Gaussian<2> g{Vec<2>(std::isfinite(a0) ? a0 : 0.0, 0.0),
                  (Covariance<2>() << 100, 0, 0, 4).finished()};
    const auto& t = d.col("t");
    for (std::size_t k = 0; k < d.rows(); ++k) {
      if (k > 0) {
        const Model md = model(t[k] - t[k - 1], gamma);
        g = predict(g, md.F, (md.B * d.col("gyro")[k - 1]).eval(),
                    (md.G * fp.N_omega * md.G.transpose()).eval());
      }
      const double z = d.col("angle")[k];
      if (k % 3 == 0 && std::isfinite(z)) {
        const Model md = model(0.02, gamma);
        const auto u =
            update(g, Vec<1>(z), md.H, Covariance<1>(Covariance<1>::Constant(fp.N_theta)));
        ASSERT_TRUE(u.ok);
        EXPECT_NEAR(r.k1[k], u.K(0, 0), 1e-12);
        EXPECT_NEAR(r.k2[k], u.K(1, 0), 1e-12);
        EXPECT_NEAR(r.nis[k], u.nis, 1e-9);
        g = u.post;
      }
      ASSERT_NEAR(r.theta[k], g.x(0), 1e-9) << "k = " << k;
      ASSERT_NEAR(r.bias[k], g.x(1), 1e-9) << "k = " << k;
      ASSERT_NEAR(r.P11[k], g.P(0, 0), 1e-9) << "k = " << k;
      ASSERT_NEAR(r.P22[k], g.P(1, 1), 1e-9) << "k = " << k;
    }
  }
}

}  // namespace
}  // namespace kfw::helicopter
