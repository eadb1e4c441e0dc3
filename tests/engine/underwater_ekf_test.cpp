// Tests of the seed 004 EKF localization (engine/scenarios/underwater/underwater_ekf.h).
#include "scenarios/underwater/underwater_ekf.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "core/scenario.h"
#include "scenarios/underwater/underwater_sim.h"

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

// The default preset (every uncertainty on, high correlation, ±1 m outliers, asynchronous) lands
// in the band of seed 004, Table 13 (RMSE 0.13–0.20 m) or better, and catches ≥ 94 % of outliers
// (Table 14: 276/276, 264/276, 276/276). The bound was 95 % before the simulators drew from the
// random-number specification (CHANGES.md, issue 27): the default seed 4 catches 262 (AS), 266
// (SC), 263 (SI) of 276 (was 269, 271, 269); seeds 1–10 with AS 262–270 (was 263–273).
TEST(UnderwaterEkf, DefaultPresetMatchesTable13And14) {
  auto sc = make_scenario("underwater");
  ASSERT_TRUE(sc);
  const ParamValues v = (*sc)->params().defaults();
  const auto d = (*sc)->simulate(v);
  ASSERT_TRUE(d) << d.error();
  for (double scheme : {0.0, 1.0, 2.0}) {
    ParamValues w = v;
    w["scheme"] = scheme;
    const auto r = (*sc)->run(*d, w);
    ASSERT_TRUE(r) << r.error();
    const Metrics& m = (*r)->metrics;
    EXPECT_LT(m.at("rmse"), 0.20) << scheme;
    EXPECT_LE(m.at("pos_mean"), m.at("rmse"));
    EXPECT_EQ(m.at("outliers_injected"), 276.0);
    EXPECT_GE(m.at("outliers_detected"), 0.94 * 276.0) << scheme;
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

Dataset without(Dataset d, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    const int i = d.index(name);
    if (i < 0) continue;
    d.names.erase(d.names.begin() + i);
    d.columns.erase(d.columns.begin() + i);
  }
  return d;
}

// Without outlier1..4 nobody knows which rejections were outliers: the counts are undefined (with
// the reason), not "every rejection is a false alarm".
TEST(UnderwaterEkf, OutlierCountsAreUnknownWithoutInjectedColumns) {
  auto sc = make_scenario("underwater");
  ASSERT_TRUE(sc);
  const ParamValues v = (*sc)->params().defaults();
  const auto d = (*sc)->simulate(v);
  ASSERT_TRUE(d) << d.error();
  const auto with = (*sc)->run(*d, v);
  ASSERT_TRUE(with) << with.error();
  EXPECT_EQ((*with)->metrics.at("outliers_injected"), 276.0);
  EXPECT_TRUE(std::isfinite((*with)->metrics.at("outliers_false_alarm")));

  const Dataset bare = without(*d, {"outlier1", "outlier2", "outlier3", "outlier4"});
  const auto r = (*sc)->run(bare, v);
  ASSERT_TRUE(r) << r.error();
  const Metrics& m = (*r)->metrics;
  for (const char* k : {"outliers_injected", "outliers_detected", "outliers_false_alarm"}) {
    EXPECT_EQ(m.count(k), 0U) << k;
    ASSERT_TRUE((*r)->undefined.count(k)) << k;
    EXPECT_NE((*r)->undefined.at(k).find("outlier1..4"), std::string::npos) << k;
  }
  // The gate still works; only the bookkeeping is unknown.
  EXPECT_EQ(m.at("ranges_rejected"), (*with)->metrics.at("ranges_rejected"));
  EXPECT_GT(m.at("ranges_rejected"), 200.0);
  // One column missing is as unknown as all four.
  const auto one = (*sc)->run(without(*d, {"outlier3"}), v);
  ASSERT_TRUE(one) << one.error();
  EXPECT_EQ((*one)->metrics.count("outliers_false_alarm"), 0U);
  EXPECT_TRUE((*one)->undefined.count("outliers_false_alarm"));
}

// NEES of (x, y, z) against truth: 3 dof, the textbook quadratic form, NaN where truth is missing.
TEST(UnderwaterEkf, NeesOfThePositionAgainstTruth) {
  auto sc = make_scenario("underwater");
  ASSERT_TRUE(sc);
  const ParamValues v = (*sc)->params().defaults();
  auto d = (*sc)->simulate(v);
  ASSERT_TRUE(d) << d.error();
  // Truth lost for a stretch of rows.
  auto& xt = d->columns[static_cast<std::size_t>(d->index("x_true"))];
  for (std::size_t k = 1000; k < 1100; ++k)
    xt[k] = kNoSample;
  for (double scheme : {0.0, 1.0, 2.0}) {
    ParamValues w = v;
    w["scheme"] = scheme;
    const auto run = (*sc)->run(*d, w);
    ASSERT_TRUE(run) << run.error();
    const auto& r = dynamic_cast<const UnderwaterResult&>(**run);
    const NeesSeries s = r.nees_series();
    EXPECT_EQ(s.dof, 3.0);
    ASSERT_EQ(s.nees.size(), r.steps());
    for (std::size_t k = 1000; k < 1100; ++k)
      EXPECT_TRUE(std::isnan(s.nees[k])) << k;
    std::size_t finite = 0;
    for (double e : s.nees)
      finite += std::isfinite(e) ? 1 : 0;
    EXPECT_EQ(finite, r.steps() - 100);
    // The quadratic form with the full covariance of the row.
    for (std::size_t k : {std::size_t{0}, r.steps() / 2, r.steps() - 1}) {
      Covariance<3> P;
      P << r.Pxx[k], r.Pxy[k], r.Pxz[k], r.Pxy[k], r.Pyy[k], r.Pyz[k], r.Pxz[k], r.Pyz[k], r.Pzz[k];
      const Vec<3> e(r.x[k] - r.x_true[k], r.y[k] - r.y_true[k], r.z[k] - r.z_true[k]);
      EXPECT_NEAR(s.nees[k], e.dot(P.inverse() * e), 1e-9 * (1.0 + s.nees[k])) << k;
    }
    // A sensible mean on the default run: nees_mean is NEES / dof, near 1 (R carries the common
    // range noise σ_c² as if it were white, so P is not far from the error).
    const double mean = r.metrics.at("nees_mean");
    EXPECT_GT(mean, 0.5) << scheme;
    EXPECT_LT(mean, 1.5) << scheme;
  }
  // Without any truth there is no NEES at all.
  const auto bare = (*sc)->run(without(*d, {"x_true", "y_true", "z_true"}), v);
  ASSERT_TRUE(bare) << bare.error();
  EXPECT_TRUE((*bare)->nees_series().nees.empty());
  EXPECT_EQ((*bare)->metrics.count("nees_mean"), 0u);
  EXPECT_FALSE((*bare)->undefined.at("nees_mean").empty());
}

}  // namespace
}  // namespace kfw::underwater
