// Issue 27 (model files, part 2), what plots are drawn from: an angle's line breaks where it
// wraps (engine/data/wrap_gaps.h), and each steady-state gain entry K.STATE.ROLE declares its
// unit [STATE]/[ROLE].
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/model_files.h"
#include "data/wrap_gaps.h"
#include "experiment/gain_curve.h"

namespace kfw {
namespace model_world_plots_test {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTurn = 2.0 * kPi;

// Largest jump between consecutive finite points of a gapped series (a NaN point resets).
double largest_jump(const std::vector<double>& y) {
  double worst = 0.0;
  for (std::size_t k = 1; k < y.size(); ++k) {
    if (std::isfinite(y[k]) && std::isfinite(y[k - 1]))
      worst = std::max(worst, std::abs(y[k] - y[k - 1]));
  }
  return worst;
}

TEST(ModelWorldPlots, AnAngleCrossingPiGetsAGapAtEachWrap) {
  // A bearing turning at 1 rad/s over 10 s: wrapped, it jumps by about −2π at t ≈ π and 3π.
  std::vector<double> t, y;
  for (int k = 0; k <= 100; ++k) {
    t.push_back(0.1 * k);
    y.push_back(std::remainder(0.1 * k, kTurn));
  }
  const GappedSeries g = gap_wraps(t, y, kTurn);
  EXPECT_EQ(g.gaps, 2u);
  EXPECT_EQ(g.t.size(), t.size() + 2);
  EXPECT_LT(largest_jump(g.y), 0.5 * kTurn);
  // Each gap sits between the samples that jumped, at the mid time.
  std::size_t seen = 0;
  for (std::size_t i = 1; i + 1 < g.y.size(); ++i) {
    if (!std::isnan(g.y[i])) continue;
    ++seen;
    EXPECT_GT(std::abs(g.y[i + 1] - g.y[i - 1]), 0.5 * kTurn);
    EXPECT_DOUBLE_EQ(g.t[i], 0.5 * (g.t[i - 1] + g.t[i + 1]));
  }
  EXPECT_EQ(seen, 2u);
  // Replay: the first k samples are the first points[k] points.
  ASSERT_EQ(g.points.size(), t.size() + 1);
  EXPECT_EQ(g.points_for(0), 0u);
  EXPECT_EQ(g.points_for(t.size()), g.t.size());
  EXPECT_EQ(g.points_for(t.size() + 50), g.t.size());
  EXPECT_EQ(g.t[g.points_for(40) - 1], t[39]);
  // Without a wrap the series is unchanged; a non-angle (turn 0) gets no gap.
  const std::vector<double> slow = {0.1, 0.2, 3.0, -3.0};
  EXPECT_EQ(gap_wraps({0, 1, 2, 3}, slow, 0.0).gaps, 0u);
  EXPECT_EQ(gap_wraps({0, 1, 2}, {0.1, 0.2, 0.3}, kTurn).y, (std::vector<double>{0.1, 0.2, 0.3}));
}

TEST(ModelWorldPlots, DegreesAndMissingSamples) {
  // 179° → −179° is a wrap in degrees; a missing sample between is left out, not a gap.
  const std::vector<double> t = {0, 1, 2, 3, 4};
  const std::vector<double> y = {170, 179, std::nan(""), -179, -170};
  const GappedSeries g = gap_wraps(t, y, 360.0);
  EXPECT_EQ(g.gaps, 1u);
  ASSERT_EQ(g.y.size(), 5u);  // 4 finite samples and one gap
  EXPECT_TRUE(std::isnan(g.y[2]));
  EXPECT_DOUBLE_EQ(g.t[2], 2.0);  // midway between t = 1 and t = 3
  EXPECT_EQ(g.points, (std::vector<std::size_t>{0, 1, 2, 2, 4, 5}));
  // 90° in a step is no wrap.
  EXPECT_EQ(gap_wraps({0, 1}, {0, 90}, 360.0).gaps, 0u);
}

TEST(ModelWorldPlots, ABandBreaksWhereItsCentreWraps) {
  const std::vector<double> t = {0, 1, 2, 3};
  const std::vector<double> x = {3.0, 3.1, -3.1, -3.0};
  const std::vector<double> lo = {2.8, 2.9, -3.3, -3.2}, hi = {3.2, 3.3, -2.9, -2.8};
  const GappedBand b = gap_band_wraps(t, x, lo, hi, kTurn);
  ASSERT_EQ(b.t.size(), 5u);
  EXPECT_TRUE(std::isnan(b.lo[2]) && std::isnan(b.hi[2]));
  EXPECT_EQ(b.hi[3], -2.9);
  EXPECT_EQ(b.points_for(4), 5u);
}

TEST(ModelWorldPlots, GainEntriesDeclareTheirUnits) {
  auto cv1d = testing::load_model("cv1d.json");
  ASSERT_TRUE(cv1d);
  // K.x.z is m/m (dimensionless), K.v.z (m/s)/m = 1/s.
  EXPECT_TRUE(is_declared_metric(*cv1d, "K.x.z"));
  EXPECT_EQ(describe_metric(*cv1d, "K.x.z").unit, "");
  EXPECT_EQ(describe_metric(*cv1d, "K.v.z").unit, "1/s");
  EXPECT_EQ(describe_metric(*cv1d, "K.v.z").group, MetricGroup::kGains);
  EXPECT_EQ(describe_metric(*cv1d, "K.v.z").direction, Direction::kNone);
  auto rb = testing::load_model("range_bearing.json");
  ASSERT_TRUE(rb);
  EXPECT_EQ(describe_metric(*rb, "K.px.range").unit, "");
  EXPECT_EQ(describe_metric(*rb, "K.px.bearing").unit, "m/rad");
  EXPECT_EQ(describe_metric(*rb, "K.vx.range").unit, "1/s");
  EXPECT_EQ(describe_metric(*rb, "K.vx.bearing").unit, "(m/s)/rad");
  // The gain curve carries them, entry by entry.
  auto curve = gain_curve(*cv1d, cv1d->params().defaults(), "sigma_a", 5);
  ASSERT_TRUE(curve.ok()) << curve.error();
  ASSERT_EQ(curve->units.size(), curve->entries.size());
  for (std::size_t e = 0; e < curve->entries.size(); ++e)
    EXPECT_EQ(curve->units[e], curve->entries[e] == "K.v.z" ? "1/s" : "") << curve->entries[e];
}

}  // namespace
}  // namespace model_world_plots_test
}  // namespace kfw
