// Line plots of a wrapped quantity (an angle kept in (−π, π] or (−180°, 180°]): where the value
// wraps, a line through the samples on either side would cross the whole plot. A gap goes there
// instead. Data preparation for plots, not filter math: the widgets draw what this returns.
#pragma once

#include <cstddef>
#include <vector>

namespace kfw {

// A series ready for a line plot with gaps: the finite samples in order, and a NaN point (at the
// mid time) between two consecutive ones that jump by more than half a turn.
struct GappedSeries {
  std::vector<double> t, y;
  // points[k]: how many points of t/y come from the input's first k samples (size: samples + 1),
  // so a replay that shows k steps shows points[k] points.
  std::vector<std::size_t> points;
  std::size_t gaps = 0;  // NaN points inserted
  std::size_t points_for(std::size_t steps) const {
    return points.empty() ? 0 : points[steps < points.size() ? steps : points.size() - 1];
  }
};

// y over t with a NaN between consecutive finite samples whose difference exceeds turn / 2
// (turn: 2π for radians, 360 for degrees; 0 or less inserts no gap). Non-finite samples are left
// out, so the line joins across a missing sample as it would without the gaps.
GappedSeries gap_wraps(const std::vector<double>& t, const std::vector<double>& y, double turn);

// The same gaps on a band around y: lo and hi over t, with a NaN pair wherever `gap_wraps` of
// the centre y puts one (the edges break where the centre does). Steps where y, lo or hi is not
// finite are left out.
struct GappedBand {
  std::vector<double> t, lo, hi;
  std::vector<std::size_t> points;
  std::size_t points_for(std::size_t steps) const {
    return points.empty() ? 0 : points[steps < points.size() ? steps : points.size() - 1];
  }
};
GappedBand gap_band_wraps(const std::vector<double>& t, const std::vector<double>& y,
                          const std::vector<double>& lo, const std::vector<double>& hi,
                          double turn);

}  // namespace kfw
