// Reduces a dense, time-ordered series to what a raster of pixel columns can show, in one pass
// over the samples of the visible range: per column the first, lowest, highest and last point
// of a line, one dot per occupied cell of a scatter, and the envelope of a band. The columns'
// index ranges are found by binary search on the (sorted) time, so the per-sample work is a
// branch-light min/max loop; what is drawn afterwards is O(columns), whatever the log's length.
// Qt-free (plot_kit.cpp turns the points into QCustomPlot data).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace kfw::plot {

struct XY {
  double x, y;
};

// A value that can be drawn: finite, and positive on a log axis.
inline bool drawable(double v, bool logY) {
  constexpr double kMax = std::numeric_limits<double>::max();
  return logY ? (v > 0.0 && v <= kMax) : std::fabs(v) <= kMax;
}

// A cheap log2 for binning on a log axis: a positive double's bits, read as an integer, grow
// with its log2 (exponent, then a linear mantissa) — within 0.09 of log2 and monotonic. Binning
// only chooses which dots share a cell; every dot drawn is exact.
inline double coarseLog2(double v) {
  std::int64_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  return static_cast<double>(bits) * 0x1p-52 - 1023.0;
}

// Calls f(s, e) for each run of samples [s, e) of x[a, b) that falls into one of `cols` equal
// columns over [x0, x1] (samples outside the range get columns of their own width beyond it).
// x must be increasing (time); a non-finite x is skipped.
template <typename F>
void forEachColumn(const double* x, std::size_t a, std::size_t b, double x0, double x1, int cols,
                   F&& f) {
  const double w = x1 > x0 && cols > 0 ? (x1 - x0) / cols : 0.0;
  std::size_t s = a;
  while (s < b) {
    if (!std::isfinite(x[s])) {
      ++s;
      continue;
    }
    std::size_t e = b;
    if (w > 0.0) {
      // The column is floor((x − x0) / w); the binary search on its right edge can be off by
      // a rounding error, so the run's end is checked against that same formula.
      auto column = [&](std::size_t i) { return std::floor((x[i] - x0) / w); };
      const double c = column(s);
      e = static_cast<std::size_t>(std::lower_bound(x + s + 1, x + b, x0 + (c + 1.0) * w) - x);
      while (e > s + 1 && column(e - 1) > c)
        --e;
      while (e < b && column(e) == c)
        ++e;
    }
    f(s, e);
    s = e;
  }
}

// Lines: per column the first, lowest, highest and last drawable point, in time order.
void reduceLine(const double* x, const double* y, std::size_t a, std::size_t b, bool logY,
                double x0, double x1, int cols, std::vector<XY>& out);

// reduceLine for a line with gaps: each run of drawable samples reduced on its own, with a NaN
// point (at the x of the first undrawable sample) between runs, so the gaps stay gaps.
void reduceLineWithGaps(const double* x, const double* y, std::size_t a, std::size_t b, bool logY,
                        double x0, double x1, int cols, std::vector<XY>& out);

// Scatter of a time-ordered series: one dot per occupied cell of a cols × rows raster over the
// drawable points' extent (dots are 2 px: cells of 2 × 2 px lose nothing visible), in time order.
void reduceDots(const double* x, const double* y, std::size_t a, std::size_t b, bool logY, int cols,
                int rows, std::vector<XY>& out);

// A band from per-step limits: limits(i, lo, hi) sets step i's lower and upper limit. Per column
// the highest upper and lowest lower limit, at the column's first time; steps with a non-finite
// limit are left out.
template <typename Limits>
void reduceBand(const double* x, std::size_t a, std::size_t b, double x0, double x1, int cols,
                Limits&& limits, std::vector<XY>& upper, std::vector<XY>& lower) {
  forEachColumn(x, a, b, x0, x1, cols, [&](std::size_t s, std::size_t e) {
    double u = -std::numeric_limits<double>::infinity();
    double l = std::numeric_limits<double>::infinity();
    std::size_t first = e;
    for (std::size_t i = s; i < e; ++i) {
      double lo = 0.0, hi = 0.0;
      limits(i, lo, hi);
      if (!drawable(lo, false) || !drawable(hi, false)) continue;
      if (first == e) first = i;
      u = std::max(u, hi);
      l = std::min(l, lo);
    }
    if (first == e) return;
    upper.push_back({x[first], u});
    lower.push_back({x[first], l});
  });
}

// The index range of the sorted x[a, b) that covers [lo, hi], with one sample beyond each edge
// (so lines leave the plot instead of stopping short of its border).
inline void visibleRange(const double* x, std::size_t& a, std::size_t& b, double lo, double hi) {
  const double* from = std::lower_bound(x + a, x + b, lo);
  const double* to = std::upper_bound(from, x + b, hi);
  if (from != x + a) --from;
  if (to != x + b) ++to;
  b = static_cast<std::size_t>(to - x);
  a = static_cast<std::size_t>(from - x);
}

}  // namespace kfw::plot
