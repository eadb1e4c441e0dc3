// Finding a better tuning: a derivative-free search (Nelder–Mead with restarts, log space for
// log-scale parameters) and grid sweeps of any metric over one or two parameters.
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/scenario.h"

namespace kfw {

struct SearchParam {
  std::string key;
  double lo = 0.0, hi = 1.0;
  bool log = false;  // search in log10 (variances)
};

// An objective to minimise from a run's metrics; NaN means "cannot evaluate" (treated as +inf).
using Objective = std::function<double(const Metrics&)>;

// Objectives by name: "rmse" (needs truth), "nll" (mean innovation negative log-likelihood),
// "nis" ((log NIS mean / dof)²), or any metric name to minimise.
Expected<Objective> objective_by_name(const std::string& name);

struct TuneOptions {
  int max_evaluations = 400;
  int restarts = 2;
  const std::atomic<bool>* cancel = nullptr;
  std::function<void(int evaluations, double best)> progress;
};

struct TuneResult {
  ParamValues best;
  double objective = 0.0;
  Metrics metrics;  // of the best run
  int evaluations = 0;
};

// Searches `params` (others held at `start`) on one dataset. Ranges come from the table unless
// narrowed in `params`.
Expected<TuneResult> tune(const Scenario& s, const Dataset& d, const ParamValues& start,
                          const std::vector<SearchParam>& params, const Objective& objective,
                          const TuneOptions& options = {});

struct SweepAxis {
  std::string key;
  double lo = 0.0, hi = 1.0;
  int n = 10;
  bool log = false;
  std::vector<double> values() const;
};

struct SweepResult {
  std::vector<SweepAxis> axes;
  std::vector<std::vector<double>> points;  // one row per grid point: the axes' values
  std::vector<Metrics> metrics;             // one per grid point (empty when the run failed)
  std::vector<std::string> errors;          // one per grid point: why its run stopped, or ""
  std::size_t stopped() const;              // how many runs stopped
};

// Runs every grid point (row-major, the first axis slowest) on `threads` threads.
Expected<SweepResult> sweep(const Scenario& s, const Dataset& d, const ParamValues& base,
                            const std::vector<SweepAxis>& axes, int threads = 2,
                            const std::atomic<bool>* cancel = nullptr);

// Parses "key=GRID" (grammar.h: lo:hi:n[:log|:lin]); without a suffix, log spacing when the
// key's scale is log.
Expected<SweepAxis> parse_sweep_axis(const ParamTable& table, const std::string& text);

}  // namespace kfw
