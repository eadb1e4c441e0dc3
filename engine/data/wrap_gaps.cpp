#include "data/wrap_gaps.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace kfw {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Visits the finite samples of y in order; `gap` is true when the sample is more than half a
// turn away from the previous finite one (and turn > 0).
template <typename F>
void visit(const std::vector<double>& t, const std::vector<double>& y, double turn, F&& f) {
  const std::size_t n = t.size() < y.size() ? t.size() : y.size();
  bool have_prev = false;
  double prev = 0.0, prev_t = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(y[k]) || !std::isfinite(t[k])) {
      f(k, false, 0.0, false);
      continue;
    }
    const bool gap = have_prev && turn > 0.0 && std::abs(y[k] - prev) > 0.5 * turn;
    f(k, gap, 0.5 * (prev_t + t[k]), true);
    have_prev = true;
    prev = y[k];
    prev_t = t[k];
  }
}

}  // namespace

GappedSeries gap_wraps(const std::vector<double>& t, const std::vector<double>& y, double turn) {
  GappedSeries g;
  const std::size_t n = t.size() < y.size() ? t.size() : y.size();
  g.t.reserve(n);
  g.y.reserve(n);
  g.points.assign(1, 0);
  g.points.reserve(n + 1);
  visit(t, y, turn, [&](std::size_t k, bool gap, double t_gap, bool keep) {
    if (gap) {
      g.t.push_back(t_gap);
      g.y.push_back(kNaN);
      ++g.gaps;
    }
    if (keep) {
      g.t.push_back(t[k]);
      g.y.push_back(y[k]);
    }
    g.points.push_back(g.t.size());
  });
  return g;
}

GappedBand gap_band_wraps(const std::vector<double>& t, const std::vector<double>& y,
                          const std::vector<double>& lo, const std::vector<double>& hi,
                          double turn) {
  GappedBand b;
  const std::size_t n = std::min({t.size(), y.size(), lo.size(), hi.size()});
  b.points.assign(1, 0);
  b.points.reserve(n + 1);
  visit(t, y, turn, [&](std::size_t k, bool gap, double t_gap, bool keep) {
    if (k >= n) return;
    if (gap) {
      b.t.push_back(t_gap);
      b.lo.push_back(kNaN);
      b.hi.push_back(kNaN);
    }
    if (keep && std::isfinite(lo[k]) && std::isfinite(hi[k])) {
      b.t.push_back(t[k]);
      b.lo.push_back(lo[k]);
      b.hi.push_back(hi[k]);
    }
    b.points.push_back(b.t.size());
  });
  return b;
}

}  // namespace kfw
