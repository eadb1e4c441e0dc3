// Tests of the seed 004 verification statistics (tests/oracles/underwater/underwater_stats.h):
// the sample covariance of simulated range/depth errors reproduces the design (Sec. 4.1–4.3).
#include "oracles/underwater/underwater_stats.h"

#include <gtest/gtest.h>

#include <cmath>

#include "oracles/underwater/underwater_sim.h"

namespace kfw::underwater {
namespace {

// A long synchronous run: 2 h at 0.5 s holds 7200 independent n_c draws (t_gap = 1 s), so the
// sample variance of n_c is within ±1.7 % (1σ) of σ_c², and 14 400 instants for the white noise.
SimParams long_run(double sigma_range, double sigma_depth, double sigma_corr) {
  SimParams p;
  p.seed = 11;
  p.duration_s = 7200.0;
  p.synchronous = true;
  p.dt_sync_s = 0.5;
  p.sigma_t_s = 0.0;
  p.sigma_range_m = sigma_range;
  p.sigma_depth_m = sigma_depth;
  p.sigma_corr_m = sigma_corr;
  p.t_gap_s = 1.0;
  p.outliers = 0;
  return p;
}

// Asserts every entry of the sample covariance against the design with relative tolerance `rel`
// on the non-zero entries and an absolute floor `abs` for entries whose design is 0.
void expect_matches_design(const ErrorStats& st, const Covariance<kErrorDims>& design, double rel,
                           double abs) {
  for (int i = 0; i < kErrorDims; ++i) {
    for (int j = 0; j < kErrorDims; ++j) {
      const double want = design(i, j);
      const double tol = want != 0.0 ? rel * want : abs;
      EXPECT_NEAR(st.covariance(i, j), want, tol) << "entry (" << i << ", " << j << ")\n"
                                                  << st.covariance << "\nvs design\n"
                                                  << design;
    }
  }
}

TEST(UnderwaterStats, DesignCovarianceIsWhitePlusCommonMode) {
  const auto C = design_covariance(0.1, 0.2, 0.2);
  EXPECT_DOUBLE_EQ(C(0, 0), 0.01 + 0.04);
  EXPECT_DOUBLE_EQ(C(1, 3), 0.04);
  EXPECT_DOUBLE_EQ(C(4, 4), 0.04);
  EXPECT_DOUBLE_EQ(C(0, 4), 0.0);
}

// Sec. 4.1, eq. 5: Gaussian only → diag ≈ 0.01 ×4 and 0.04, off-diagonals ≈ 0.
TEST(UnderwaterStats, GaussianOnlyReproducesEq5) {
  const auto st = error_stats(simulate(long_run(0.1, 0.2, 0.0)));
  ASSERT_TRUE(st) << st.error();
  EXPECT_EQ(st->instants, 14401u);
  expect_matches_design(*st, design_covariance(0.1, 0.0, 0.2), 0.05, 0.0008);
}

// Sec. 4.2, eq. 6: correlation only, σ_c = 0.2, t_gap = 1 s → range block ≈ σ_c² = 0.04 (the
// paper's 0.032 was one 3-min run), depth row and column exactly 0.
TEST(UnderwaterStats, HighCorrelationOnlyConvergesToSigmaC2) {
  const auto st = error_stats(simulate(long_run(0.0, 0.0, 0.2)));
  ASSERT_TRUE(st) << st.error();
  expect_matches_design(*st, design_covariance(0.0, 0.2, 0.0), 0.06, 1e-12);
  for (int i = 0; i < kErrorDims; ++i)
    EXPECT_NEAR(st->covariance(4, i), 0.0, 1e-12);
}

// Sec. 4.2, eq. 7: σ_c = 0.05 → ≈ 0.0025.
TEST(UnderwaterStats, LowCorrelationOnlyConvergesToSigmaC2) {
  const auto st = error_stats(simulate(long_run(0.0, 0.0, 0.05)));
  ASSERT_TRUE(st) << st.error();
  expect_matches_design(*st, design_covariance(0.0, 0.05, 0.0), 0.06, 1e-12);
}

// Sec. 4.3, eq. 8: both → the sum (diag 0.05, off 0.04, depth 0.04).
TEST(UnderwaterStats, GaussianPlusCorrelationIsTheSum) {
  const auto st = error_stats(simulate(long_run(0.1, 0.2, 0.2)));
  ASSERT_TRUE(st) << st.error();
  expect_matches_design(*st, design_covariance(0.1, 0.2, 0.2), 0.06, 0.0008);
}

// The paper's 3-minute, 0.1 s run lands in the band the paper reports for eq. 5 (within 15 %).
TEST(UnderwaterStats, ThreeMinuteRunIsWithin15PercentLikeThePaper) {
  SimParams p = long_run(0.1, 0.2, 0.0);
  p.duration_s = 180.0;
  p.dt_sync_s = 0.1;
  const auto st = error_stats(simulate(p));
  ASSERT_TRUE(st) << st.error();
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(st->covariance(i, i), 0.01, 0.0015);
  EXPECT_NEAR(st->covariance(4, 4), 0.04, 0.006);
}

// Asynchronous clocks with jitter: instants are formed when every sensor has a new sample.
TEST(UnderwaterStats, AsynchronousLogStillHasInstants) {
  SimParams p;
  p.duration_s = 60.0;
  p.sigma_t_s = 0.002;
  p.sigma_corr_m = 0.0;
  const auto st = error_stats(simulate(p));
  ASSERT_TRUE(st) << st.error();
  EXPECT_GT(st->instants, 400u);
  EXPECT_NEAR(st->covariance(4, 4), 0.04, 0.012);
}

// Injected outliers are counted and kept out of the covariance.
TEST(UnderwaterStats, OutliersAreCountedAndExcluded) {
  SimParams p = long_run(0.1, 0.2, 0.0);
  p.duration_s = 600.0;
  p.outliers = 100;
  p.outlier_m = 1.0;
  const auto st = error_stats(simulate(p));
  ASSERT_TRUE(st) << st.error();
  EXPECT_EQ(st->outliers_injected, 100u);
  EXPECT_GT(st->outlier_instants, 90u);  // a few instants hold two
  EXPECT_EQ(st->instants + st->outlier_instants, 1201u);
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(st->covariance(i, i), 0.01, 0.002);
}

TEST(UnderwaterStats, MissingTruthColumnIsNamed) {
  SimParams p;
  p.duration_s = 2.0;
  Dataset d = simulate(p);
  const int i = d.index("z_true");
  d.names.erase(d.names.begin() + i);
  d.columns.erase(d.columns.begin() + i);
  const auto st = error_stats(d);
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().find("z_true"), std::string::npos) << st.error();
}

}  // namespace
}  // namespace kfw::underwater
