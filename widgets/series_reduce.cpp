#include "series_reduce.h"

#include <cstdint>

namespace kfw::plot {

void reduceLine(const double* x, const double* y, std::size_t a, std::size_t b, bool logY,
                double x0, double x1, int cols, std::vector<XY>& out) {
  forEachColumn(x, a, b, x0, x1, cols, [&](std::size_t s, std::size_t e) {
    std::size_t first = s;
    while (first < e && !drawable(y[first], logY))
      ++first;
    if (first == e) return;
    std::size_t last = e - 1;
    while (!drawable(y[last], logY))
      --last;
    std::size_t lo = first, hi = first;
    double vlo = y[first], vhi = y[first];
    for (std::size_t i = first + 1; i <= last; ++i) {
      const double v = y[i];
      if (!drawable(v, logY)) continue;
      if (v < vlo) {
        vlo = v;
        lo = i;
      }
      if (v > vhi) {
        vhi = v;
        hi = i;
      }
    }
    std::size_t idx[4] = {first, std::min(lo, hi), std::max(lo, hi), last};
    std::size_t prev = e;  // no index yet
    for (std::size_t i : idx) {
      if (i == prev) continue;
      out.push_back({x[i], y[i]});
      prev = i;
    }
  });
}

void reduceLineWithGaps(const double* x, const double* y, std::size_t a, std::size_t b, bool logY,
                        double x0, double x1, int cols, std::vector<XY>& out) {
  std::size_t s = a;
  while (s < b) {
    std::size_t e = s;
    while (e < b && drawable(y[e], logY))
      ++e;
    if (e > s) reduceLine(x, y, s, e, logY, x0, x1, cols, out);
    if (e < b && std::isfinite(x[e]) && !out.empty() && std::isfinite(out.back().y)) {
      out.push_back({x[e], std::numeric_limits<double>::quiet_NaN()});
    }
    s = e + 1;
  }
}

void reduceDots(const double* x, const double* y, std::size_t a, std::size_t b, bool logY, int cols,
                int rows, std::vector<XY>& out) {
  // Rows over the drawable values' extent (log2 on a log axis: a coarse log is enough to choose
  // which dots share a cell; every dot drawn is exact).
  auto fy = [logY](double v) { return logY ? coarseLog2(v) : v; };
  double y0 = std::numeric_limits<double>::infinity(), y1 = -y0;
  std::size_t first = b, last = a;
  for (std::size_t i = a; i < b; ++i) {
    const double v = y[i];
    if (!drawable(v, logY) || !std::isfinite(x[i])) continue;
    y0 = std::min(y0, v);
    y1 = std::max(y1, v);
    first = std::min(first, i);
    last = i;
  }
  if (first == b) return;
  const double fy0 = fy(y0), fspan = fy(y1) - fy0;
  const double rscale = fspan > 0 ? rows / fspan : 0.0;
  std::vector<std::uint64_t> seen(static_cast<std::size_t>(rows) / 64 + 1);
  forEachColumn(x, first, last + 1, x[first], x[last], cols, [&](std::size_t s, std::size_t e) {
    std::fill(seen.begin(), seen.end(), 0);
    // Branch-free: every drawable dot is written, and the count moves on only for a cell seen
    // for the first time (whether a cell is new is a coin toss the branch predictor loses).
    std::size_t kept = out.size();
    out.resize(kept + (e - s));
    for (std::size_t i = s; i < e; ++i) {
      const double v = y[i];
      if (!drawable(v, logY)) continue;
      const auto r = static_cast<std::size_t>(
          std::clamp((fy(v) - fy0) * rscale, 0.0, static_cast<double>(rows)));
      std::uint64_t& word = seen[r / 64];
      const std::uint64_t bit = std::uint64_t{1} << (r % 64);
      out[kept] = {x[i], v};
      kept += (word & bit) == 0 ? 1 : 0;
      word |= bit;
    }
    out.resize(kept);
  });
}

}  // namespace kfw::plot
