// Monte Carlo runs: the simulator and the filter for every seed of a set (the `sim.seed`
// parameter), on a thread pool. What the runs leave behind is a part: the metrics of each seed and
// the per-step sums of NEES and of each channel's NIS over the runs (sufficient statistics), so
// parts from shards merge exactly into the part of the whole set.
//
// The consistency test over N runs (Bar-Shalom, Li, Kirubarajan 2001, sec. 5.4.2):
//   ANEES_k = (1/N) Σ_i NEES_k^i,  N·ANEES_k ~ χ²(N·n)   (n: states with truth)
//   ANIS_k  = (1/N) Σ_i NIS_k^i,   N·ANIS_k  ~ χ²(N·m)   (m: the channel's dimension)
// with two-sided 95 % bounds [χ²_{0.025}(N n)/N, χ²_{0.975}(N n)/N]. At a step where only c < N
// runs have a value (a channel that did not update, a run that ended early), c replaces N.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/expected.h"
#include "core/metrics.h"
#include "core/scenario.h"
#include "experiment/grammar.h"
#include "experiment/tuning.h"

namespace kfw {

// The "kind" of a Monte Carlo part file (`kfw-cli merge` dispatches on it).
inline constexpr const char* kMonteCarloKind = "montecarlo";
inline constexpr int kMonteCarloPartVersion = 2;  // written; 1 and 2 are read

// Σ v_k, Σ v_k² and the number of runs with a finite v_k, per step k.
struct StepSums {
  std::string name;   // "nees", or the channel's identifier
  std::string label;  // for tables and plots
  double dof = 1.0;   // NEES: states with truth; NIS: the channel's dimension
  std::vector<double> sum, sum_sq;
  std::vector<std::size_t> count;
  // Adds one run's series (non-finite entries are skipped; a longer series extends the sums).
  void add(const std::vector<double>& v);
  // Adds another set of sums of the same quantity.
  Status merge(const StepSums& other);
};

// One seed's run: its metrics, or why it stopped.
struct SeedRun {
  long long seed = 0;
  Metrics metrics;
  UndefinedMetrics undefined;
  std::vector<std::string> warnings;
  std::string error;  // non-empty: the run stopped (numerical breakdown); not in the statistics
  std::shared_ptr<const RunResult> result;  // only with MonteCarloOptions::keep_results
  bool stopped() const { return !error.empty(); }
};

// What a set of runs leaves behind (one shard of a seed set, or all of it).
struct MonteCarloPart {
  std::string scenario;          // the scenario's name
  std::string source;            // the preset as given on the command line (informational)
  std::vector<long long> seeds;  // the whole set, sorted
  Shard shard;                   // which members of `seeds` this part holds (1/1: all)
  std::vector<SeedRun> runs;     // sorted by seed
  std::vector<double> t;         // step times of the longest run
  std::optional<StepSums> nees;  // when the runs have truth
  std::vector<StepSums> nis;     // one per innovation channel
  // The primary state's error x̂ − x and the filter's variance P, per step (when it has truth).
  std::optional<StepSums> error, variance;
  std::string error_unit;
  // Version 2: what makes two parts parts of one run — the preset's content hash (FNV-1a 64 of
  // its file, hex) and every parameter value but sim.seed. Empty in a version-1 part (then merge
  // cannot check sameness, and says so).
  int version = kMonteCarloPartVersion;
  std::string preset_hash;
  ParamValues values;
};

struct MetricSummary {
  std::size_t n = 0;  // seeds where the metric is defined
  double mean = 0.0, sd = 0.0, min = 0.0, max = 0.0;
};

// ANEES or ANIS over the runs, per step, against the χ² bounds for the runs behind each step.
struct ConsistencySummary {
  std::string name, label;
  double dof = 1.0;
  std::size_t runs = 0;                     // the most runs behind one step (N)
  double lo = 0.0, hi = 0.0;                // the bounds for N runs
  std::vector<double> average, lo_k, hi_k;  // per step; NaN where no run has a value
  double time_average = 0.0;                // mean of the per-step averages
  double inside = 0.0;                      // fraction of steps whose average is inside its bounds
};

// The error over the seeds against what the filter claims: the mean and sd of x̂_k − x_k over
// the runs, and the filter's σ_k = √(mean P_k). A consistent filter has sd ≈ σ.
struct ErrorBand {
  std::string state, label, unit;
  std::vector<double> mean, sd, filter_sigma;  // per step; NaN where no run has a value
};

struct MonteCarloSummary {
  std::string scenario;
  std::size_t seeds = 0, completed = 0;
  std::vector<SeedRun> stopped;  // seed and error
  std::map<std::string, MetricSummary> metrics;
  UndefinedMetrics undefined;  // undefined in every completed seed: the first seed's reason
  std::vector<double> t;
  std::optional<ConsistencySummary> nees;
  std::vector<ConsistencySummary> nis;
  std::optional<ErrorBand> error;
};

struct MonteCarloOptions {
  int threads = 0;            // 0: every core
  bool keep_results = false;  // keep each run's result (estimates files, plots)
  const std::atomic<bool>* cancel = nullptr;
  // Called after each run, from a worker thread: runs done, runs in this part.
  std::function<void(std::size_t, std::size_t)> progress;
};

// Simulates and filters each seed of `seeds` that is in `shard` (`base` with sim.seed set).
// A seed outside sim.seed's range, or a scenario without a simulator seed, is an Error (exit 2,
// before any run); a run that stops is recorded in its SeedRun. Cancelled: a failure.
Expected<MonteCarloPart> run_monte_carlo(const Scenario& s, const ParamValues& base,
                                         const std::vector<long long>& seeds,
                                         const Shard& shard = {},
                                         const MonteCarloOptions& options = {});

// Mean, sd (n − 1), min and max of each metric over the seeds where it is defined, and ANEES_k /
// ANIS_k with their two-sided (1 − alpha) bounds.
MonteCarloSummary summarize_monte_carlo(const MonteCarloPart& part, double alpha = 0.05);

// Combines the parts of one seed set (one per shard, any order) into the part of the whole set.
// Parts of different scenarios, seed sets or shard counts, or a shard given twice or missing,
// are refused with a message naming the part (`names[i]`, e.g. its file).
// Version-2 parts must agree on preset_hash and values (an Error naming the part and the key);
// `notes` (may be null) gets one line when a version-1 part makes that check impossible.
Expected<MonteCarloPart> merge_montecarlo_parts(const std::vector<MonteCarloPart>& parts,
                                                const std::vector<std::string>& names = {},
                                                std::vector<std::string>* notes = nullptr);

// Each metric's mean over the seeds where it is defined (the seeds' typical result): what
// `sweep --seeds` scores a grid point by, and what a tuner can score an evaluation by. A metric
// undefined in every seed is absent; when every run stopped, the failure of the first.
Expected<Metrics> mean_metrics_over_seeds(const Scenario& s, const ParamValues& values,
                                          const std::vector<long long>& seeds,
                                          const MonteCarloOptions& options = {});

// A grid sweep (row-major, the first axis slowest) whose points are scored by
// mean_metrics_over_seeds; a point where every seed stopped carries the first error.
Expected<SweepResult> sweep_over_seeds(const Scenario& s, const ParamValues& base,
                                       const std::vector<SweepAxis>& axes,
                                       const std::vector<long long>& seeds,
                                       const MonteCarloOptions& options = {});

// A part as JSON ({"kind": "montecarlo", "version": 1, ...}; doubles round-trip exactly).
nlohmann::ordered_json part_to_json(const MonteCarloPart& part);
// Reads a part; errors name `where` and the key.
Expected<MonteCarloPart> part_from_json(const nlohmann::json& j, const std::string& where);

// The summary as JSON; with `steps`, the per-step arrays (t, ANEES_k, bounds, ANIS_k).
nlohmann::ordered_json summary_to_json(const MonteCarloSummary& s, bool steps = true);
// The summary as a readable table (metric, n, mean, sd, min, max; then the consistency lines).
std::string summary_table(const MonteCarloSummary& s);

}  // namespace kfw
