// Tests of the seed 004 EKF localization (tests/oracles/underwater/underwater_ekf.h, the retired
// built-in's EKF). Its numbers on the seed preset: underwater_preset_test.cpp.
#include "oracles/underwater/underwater_ekf.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/dataset.h"
#include "oracles/underwater/underwater_sim.h"

namespace kfw::underwater {
namespace {

double rmse(const UnderwaterResult& r) {
  double s = 0;
  std::size_t n = 0;
  for (double e : r.pos_err) {
    if (std::isfinite(e)) {
      s += e * e;
      ++n;
    }
  }
  return n ? std::sqrt(s / static_cast<double>(n)) : kNoSample;
}

SimParams quiet() {
  SimParams p;
  p.duration_s = 60.0;
  p.motion_sigma.setZero();
  p.velocity_sigma.setZero();
  p.sigma_range_m = 0.0;
  p.sigma_depth_m = 0.0;
  p.sigma_corr_m = 0.0;
  p.outliers = 0;
  return p;
}

TEST(UnderwaterEkf, RangeJacobianMatchesFiniteDifference) {
  const Vec<3> X(1.0, -2.0, 7.0);
  for (const auto& B : beacons()) {
    const auto H = range_jacobian(X, B);
    for (int i = 0; i < 3; ++i) {
      Vec<3> dx = Vec<3>::Zero();
      dx(i) = 1e-6;
      const double fd = (predicted_range(X + dx, B) - predicted_range(X - dx, B)) / 2e-6;
      EXPECT_NEAR(H(i), fd, 1e-8);
    }
    EXPECT_NEAR(H.norm(), 1.0, 1e-12);
  }
}

// Noise-free sensors: dead reckoning plus exact ranges track the truth to millimetres.
TEST(UnderwaterEkf, NoiseFreeDataIsTrackedForEveryScheme) {
  const Dataset d = simulate(quiet());
  for (Scheme s : {Scheme::kAS, Scheme::kSC, Scheme::kSI}) {
    FilterParams f;
    f.scheme = s;
    f.sigma_range_m = 0.01;
    f.sigma_depth_m = 0.01;
    f.corr_in_R = false;
    f.q_pos = 0.01;
    const auto r = run_ekf(d, f);
    ASSERT_TRUE(r) << r.error();
    EXPECT_LT(rmse(*r), 0.02) << static_cast<int>(s);
    EXPECT_EQ(r->ranges_rejected, 0u);
    for (std::size_t k = 0; k < r->steps(); ++k) {
      ASSERT_GT(r->Pxx[k], 0.0);
      ASSERT_GT(r->Pzz[k], 0.0);
    }
  }
}

// Independent range noise (no correlated term in R): one stacked update (SC) equals the same ranges
// applied one by one (SI) up to the relinearisation between them: second order in the update
// step over the range (20–45 m), so negligible once the start-up transient is over.
TEST(UnderwaterEkf, StackedEqualsSequentialForIndependentNoise) {
  SimParams p;
  p.duration_s = 60.0;
  p.synchronous = true;
  p.sigma_corr_m = 0.0;
  p.outliers = 0;
  const Dataset d = simulate(p);
  FilterParams f;
  f.corr_in_R = false;
  f.gate = 50.0;
  f.scheme = Scheme::kSC;
  const auto sc = run_ekf(d, f);
  f.scheme = Scheme::kSI;
  const auto si = run_ekf(d, f);
  ASSERT_TRUE(sc && si);
  double worst = 0;
  for (std::size_t k = 0; k < sc->steps(); ++k) {
    if (sc->t[k] < 5.0) continue;
    worst = std::max(worst, std::abs(sc->x[k] - si->x[k]) + std::abs(sc->y[k] - si->y[k]) +
                                std::abs(sc->z[k] - si->z[k]));
  }
  EXPECT_LT(worst, 1e-3);  // vs a position error of ~0.07 m
}

// χ² gate: ±1 m outliers against σ = 0.1 m ranges are all caught (seed 004, Table 14: 276/276),
// and a wide-open gate rejects nothing.
TEST(UnderwaterEkf, GateCatchesOutliersAndOpenGateRejectsNone) {
  SimParams p;
  p.sigma_corr_m = 0.0;
  p.outliers = 276;
  p.outlier_m = 1.0;
  const Dataset d = simulate(p);
  FilterParams f;
  f.corr_in_R = false;
  for (Scheme s : {Scheme::kAS, Scheme::kSC, Scheme::kSI}) {
    f.scheme = s;
    f.gate = 2.5;
    const auto r = run_ekf(d, f);
    ASSERT_TRUE(r) << r.error();
    EXPECT_EQ(r->outliers_injected, 276u);
    EXPECT_EQ(r->outliers_detected, 276u) << static_cast<int>(s);
    f.gate = 50.0;
    const auto open = run_ekf(d, f);
    EXPECT_EQ(open->ranges_rejected, 0u);
  }
}

TEST(UnderwaterEkf, BadInputIsReportedNotCrashed) {
  Dataset d = simulate(quiet());
  // A range ≤ 0 and an infinite one: recorded as invalid samples.
  auto& r1 = d.columns[static_cast<std::size_t>(d.index("range1"))];
  std::size_t bad = 0;
  for (std::size_t k = 0; k < r1.size() && bad < 2; ++k) {
    if (std::isfinite(r1[k])) r1[k] = bad++ == 0 ? -3.0 : INFINITY;
  }
  const auto r = run_ekf(d, FilterParams{});
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->ranges_invalid, 2u);
  EXPECT_FALSE(r->warnings.empty());
  // Non-monotonic time.
  Dataset back = d;
  auto& t = back.columns[static_cast<std::size_t>(back.index("t"))];
  std::swap(t[10], t[11]);
  const auto rb = run_ekf(back, FilterParams{});
  ASSERT_FALSE(rb);
  EXPECT_NE(rb.error().find("row 12"), std::string::npos) << rb.error();
  // A missing beacon column.
  Dataset miss = d;
  const int i = miss.index("range4");
  miss.names.erase(miss.names.begin() + i);
  miss.columns.erase(miss.columns.begin() + i);
  const auto rm = run_ekf(miss, FilterParams{});
  ASSERT_FALSE(rm);
  EXPECT_NE(rm.error().find("range4"), std::string::npos) << rm.error();
}

// Dropped range samples show up as missing in the timing raster.
TEST(UnderwaterEkf, DropoutsAreListedAsMissing) {
  SimParams p = quiet();
  p.range_dropout = 0.2;
  const auto r = run_ekf(simulate(p), FilterParams{});
  ASSERT_TRUE(r) << r.error();
  const double expected = 0.2 * 600;
  EXPECT_NEAR(static_cast<double>(r->missing_t[kRange2].size()), expected, 0.35 * expected);
  EXPECT_TRUE(r->missing_t[kAhrs].empty());
}

}  // namespace
}  // namespace kfw::underwater
