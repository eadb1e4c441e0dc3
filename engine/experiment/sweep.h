// Grid sweeps of any metric over one or more parameters: every grid point is an independent run,
// so a sweep can be split into shards (grammar.h, `i/N`) that run anywhere and merge exactly.
#pragma once

#include <atomic>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/scenario.h"
#include "experiment/grammar.h"

namespace kfw {

struct SweepAxis {
  std::string key;
  double lo = 0.0, hi = 1.0;
  int n = 10;
  bool log = false;
  std::vector<double> values() const;
};

struct SweepResult {
  std::vector<SweepAxis> axes;
  std::vector<std::size_t> indices;         // each point's row-major index in the whole grid
  std::vector<std::vector<double>> points;  // one row per point run: the axes' values
  std::vector<Metrics> metrics;             // one per point (empty when the run failed)
  std::vector<std::string> errors;          // one per point: why its run stopped, or ""
  std::size_t stopped() const;              // how many runs stopped
};

// The number of points of a grid, or nullopt when it exceeds `limit`.
// The coordinates of the point with row-major `index` (the last axis fastest) on a grid of the
// axes' `values`.
std::vector<double> grid_point(const std::vector<std::vector<double>>& values, std::size_t index);
std::optional<std::size_t> grid_size(const std::vector<SweepAxis>& axes, std::size_t limit);
// How many of `total` work items fall in a shard.
std::size_t shard_size(std::size_t total, const Shard& shard);

// Runs every grid point (row-major, the first axis slowest) on `threads` threads (0: every core);
// with a shard, only the points in it (in_shard of their index). `progress` (may be empty) is
// called from the workers with the number of points done.
Expected<SweepResult> sweep(const Scenario& s, const Dataset& d, const ParamValues& base,
                            const std::vector<SweepAxis>& axes, int threads = 0,
                            const std::atomic<bool>* cancel = nullptr, const Shard& shard = {},
                            const std::function<void(std::size_t done)>& progress = {});

// Parses "key=GRID" (grammar.h: lo:hi:n[:log|:lin]); without a suffix, log spacing when the
// key's scale is log.
Expected<SweepAxis> parse_sweep_axis(const ParamTable& table, const std::string& text);

}  // namespace kfw
