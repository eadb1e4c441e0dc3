// The column reducers against the definition: per pixel column of the raster, the reduced
// series holds the same extremes, ends and occupied cells as the full one.
#include "series_reduce.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

namespace kfw::plot {
namespace {

struct Series {
  std::vector<double> x, y;
};

// Uneven time (a real log's jitter), noise, a few gaps (NaN) and a spike.
Series jittered(std::size_t n, unsigned seed) {
  Series s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dt(0.005, 0.015);
  std::normal_distribution<double> noise(0.0, 0.3);
  double t = 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    t += dt(rng);
    s.x.push_back(t);
    double v = std::sin(0.003 * static_cast<double>(i)) + noise(rng);
    if (i % 97 == 5) v = std::nan("");
    if (i == n / 3) v = 40.0;
    s.y.push_back(v);
  }
  return s;
}

long columnOf(double x, double x0, double x1, int cols) {
  return static_cast<long>(std::floor((x - x0) / ((x1 - x0) / cols)));
}

TEST(SeriesReduce, ColumnsPartitionTheSamplesInOrder) {
  const auto s = jittered(20000, 1);
  const double x0 = s.x.front(), x1 = s.x.back();
  std::size_t next = 0;
  long last_col = -1;
  forEachColumn(s.x.data(), 0, s.x.size(), x0, x1, 300, [&](std::size_t a, std::size_t b) {
    EXPECT_EQ(a, next);
    EXPECT_LT(a, b);
    const long c = columnOf(s.x[a], x0, x1, 300);
    EXPECT_GT(c, last_col);
    for (std::size_t i = a; i < b; ++i)
      EXPECT_EQ(columnOf(s.x[i], x0, x1, 300), c) << i;
    last_col = c;
    next = b;
  });
  EXPECT_EQ(next, s.x.size());
}

TEST(SeriesReduce, LineKeepsEachColumnsEndsAndExtremes) {
  const auto s = jittered(50000, 2);
  const double x0 = s.x.front(), x1 = s.x.back();
  const int cols = 400;
  std::vector<XY> out;
  reduceLine(s.x.data(), s.y.data(), 0, s.x.size(), false, x0, x1, cols, out);
  EXPECT_LT(out.size(), 4U * cols + 4);
  // The definition, column by column: first, min, max and last finite sample.
  struct Col {
    double first_x, last_x, lo = INFINITY, hi = -INFINITY;
    bool any = false;
  };
  std::map<long, Col> want;
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (!std::isfinite(s.y[i])) continue;
    Col& c = want[columnOf(s.x[i], x0, x1, cols)];
    if (!c.any) c.first_x = s.x[i];
    c.any = true;
    c.last_x = s.x[i];
    c.lo = std::min(c.lo, s.y[i]);
    c.hi = std::max(c.hi, s.y[i]);
  }
  std::map<long, Col> got;
  double prev = -INFINITY;
  for (const XY& p : out) {
    EXPECT_GT(p.x, prev);  // time order, no duplicates
    prev = p.x;
    Col& c = got[columnOf(p.x, x0, x1, cols)];
    if (!c.any) c.first_x = p.x;
    c.any = true;
    c.last_x = p.x;
    c.lo = std::min(c.lo, p.y);
    c.hi = std::max(c.hi, p.y);
  }
  ASSERT_EQ(got.size(), want.size());
  for (const auto& [col, w] : want) {
    const Col& g = got.at(col);
    EXPECT_EQ(g.first_x, w.first_x) << col;
    EXPECT_EQ(g.last_x, w.last_x) << col;
    EXPECT_EQ(g.lo, w.lo) << col;
    EXPECT_EQ(g.hi, w.hi) << col;
  }
}

TEST(SeriesReduce, DotsKeepEveryOccupiedCellOnce) {
  const auto s = jittered(60000, 3);
  const int cols = 300, rows = 150;
  std::vector<XY> out;
  reduceDots(s.x.data(), s.y.data(), 0, s.x.size(), false, cols, rows, out);
  // The raster over the drawable samples' extent: the kept dots occupy exactly the cells the
  // samples occupy, one dot each, and every kept dot is a sample, in time order.
  double lo = INFINITY, hi = -INFINITY, t0 = INFINITY, t1 = -INFINITY;
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (!std::isfinite(s.y[i])) continue;
    lo = std::min(lo, s.y[i]);
    hi = std::max(hi, s.y[i]);
    t0 = std::min(t0, s.x[i]);
    t1 = std::max(t1, s.x[i]);
  }
  auto cell = [&](double x, double y) {
    const long r = std::clamp(static_cast<long>((y - lo) * (rows / (hi - lo))), 0L, long{rows});
    return std::pair<long, long>(columnOf(x, t0, t1, cols), r);
  };
  std::set<std::pair<long, long>> want, got;
  std::set<std::pair<double, double>> samples;
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (!std::isfinite(s.y[i])) continue;
    want.insert(cell(s.x[i], s.y[i]));
    samples.insert({s.x[i], s.y[i]});
  }
  double prev = -INFINITY;
  for (const XY& p : out) {
    EXPECT_GE(p.x, prev);
    prev = p.x;
    EXPECT_TRUE(samples.count({p.x, p.y}));
    EXPECT_TRUE(got.insert(cell(p.x, p.y)).second) << "two dots in one cell";
  }
  EXPECT_EQ(got, want);
  EXPECT_LT(out.size(), samples.size() / 2);
}

TEST(SeriesReduce, DotsOnALogAxisKeepEveryDecadeAndDropNonPositive) {
  auto s = jittered(60000, 6);
  for (double& v : s.y)
    v = std::isfinite(v) ? std::exp(3.0 * v) : v;
  s.y[10] = -1.0;
  s.y[11] = 0.0;
  std::vector<XY> out;
  reduceDots(s.x.data(), s.y.data(), 0, s.x.size(), true, 300, 150, out);
  std::set<int> want, got;
  for (double v : s.y)
    if (v > 0 && std::isfinite(v)) want.insert(static_cast<int>(std::floor(std::log10(v))));
  for (const XY& p : out) {
    ASSERT_GT(p.y, 0.0);
    got.insert(static_cast<int>(std::floor(std::log10(p.y))));
  }
  EXPECT_EQ(got, want);
}

TEST(SeriesReduce, BandIsTheColumnEnvelope) {
  const auto s = jittered(40000, 4);
  const double x0 = s.x.front(), x1 = s.x.back();
  const int cols = 350;
  std::vector<XY> up, low;
  reduceBand(
      s.x.data(), 0, s.x.size(), x0, x1, cols,
      [&](std::size_t i, double& lo, double& hi) {
        lo = s.y[i] - 0.5;
        hi = s.y[i] + 0.25;
      },
      up, low);
  ASSERT_EQ(up.size(), low.size());
  std::map<long, std::pair<double, double>> want;
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (!std::isfinite(s.y[i])) continue;
    auto [it, fresh] = want.try_emplace(columnOf(s.x[i], x0, x1, cols), INFINITY, -INFINITY);
    it->second.first = std::min(it->second.first, s.y[i] - 0.5);
    it->second.second = std::max(it->second.second, s.y[i] + 0.25);
  }
  ASSERT_EQ(up.size(), want.size());
  std::size_t k = 0;
  for (const auto& [col, w] : want) {
    EXPECT_EQ(columnOf(up[k].x, x0, x1, cols), col);
    EXPECT_EQ(low[k].y, w.first);
    EXPECT_EQ(up[k].y, w.second);
    ++k;
  }
}

TEST(SeriesReduce, VisibleRangeHasOneSampleBeyondEachEdge) {
  const auto s = jittered(1000, 5);
  std::size_t a = 0, b = s.x.size();
  visibleRange(s.x.data(), a, b, s.x[100] + 1e-9, s.x[200] - 1e-9);
  EXPECT_EQ(a, 100U);
  EXPECT_EQ(b, 201U);
}

}  // namespace
}  // namespace kfw::plot
