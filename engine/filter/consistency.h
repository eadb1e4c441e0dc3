// Filter consistency from innovations: NIS bounds, moving averages, whiteness (seed-independent
// textbook tests: Bar-Shalom, Li, Kirubarajan 2001, ch. 5.4; Ljung & Box 1978).
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/metrics.h"

namespace kfw {

// Two-sided (1 - alpha) χ² bounds of the NIS for `dof` degrees of freedom, averaged over `window`
// samples (the window mean of NIS is χ²(dof·window)/window).
struct NisBounds {
  double lo = 0.0, hi = 0.0;
};
NisBounds nis_bounds(double dof, std::size_t window = 1, double alpha = 0.05);

// Moving average of the finite entries over the last `window` finite samples; NaN elsewhere.
std::vector<double> moving_average_finite(const std::vector<double>& v, std::size_t window);

// Normalised autocorrelation of the finite entries (compressed to the channel's own rate) at
// lags 0..max_lag; r[0] = 1.
std::vector<double> autocorrelation(const std::vector<double>& v, std::size_t max_lag);

struct Whiteness {
  std::vector<double> acf;  // lags 0..max_lag
  double band = 0.0;        // ±1.96/√N
  double q = 0.0;           // Ljung–Box statistic
  double p_value = 0.0;     // P(χ²(max_lag) > q): small means "not white"
  std::size_t n = 0;        // samples used
};
// Ljung–Box test on the finite entries (use normalised innovations y/√S).
Whiteness ljung_box(const std::vector<double>& v, std::size_t max_lag = 20);

struct InnovationChannel;
struct NeesSeries;

// The shared consistency metrics (metrics.h): nis_mean (NIS/dof over every update), nis_mean.<ch>
// (raw), nis_in_bounds, nll (when every channel reports log det S), whiteness_p (worst channel)
// and whiteness_p.<ch> (a channel of several components: its worst component, each reported as
// whiteness_p.<ch>.<role>), nees_mean (NEES/dof) and nees_in_bounds. Keys already present are kept
// (a whiteness_p.<ch> already present is not computed again but counts for the worst channel);
// what cannot be computed goes to `undefined` with the reason.
void add_consistency_metrics(const std::vector<InnovationChannel>& channels, const NeesSeries& nees,
                             Metrics& metrics, UndefinedMetrics& undefined);

}  // namespace kfw
