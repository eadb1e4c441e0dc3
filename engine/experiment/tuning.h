// Finding a better tuning with NLopt: a local bounded method (BOBYQA, Sbplx) or a global one
// (DIRECT-L, CRS2, each polished locally), in log10 space for log-scale parameters, over one or
// many datasets. An objective is a metric judged by its declared direction (metrics.h) or
// "rmse+nis" (RMSE subject to a consistent NIS). For the keys of a scale group (noise variances
// that scale together) the tuner checks numerically whether the objective can tell their common
// scale; when it cannot, it tunes the shape by the objective and the scale by consistency (NIS
// mean / dof = 1), and says so.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/scenario.h"
#include "document/preset.h"
#include "experiment/sweep.h"

namespace kfw {

enum class TuneMethod { kBobyqa, kSbplx, kDirect, kCrs };
const char* tune_method_name(TuneMethod m);  // "bobyqa", "sbplx", "direct", "crs"
std::vector<std::string> tune_method_names();
Expected<TuneMethod> parse_tune_method(std::string_view name);

// How the per-dataset values combine: their mean, or the worst by the metric's direction.
enum class Aggregate { kMean, kWorst };
Expected<Aggregate> parse_aggregate(std::string_view name);
const char* aggregate_name(Aggregate a);

// The combined objectives (rmse+nis, rmse+anis) are declared in core/metrics.h.
struct TuneObjective {
  std::string name;           // "rmse", "nis_mean", "rmse+nis", "rmse+anis"
  MetricSpec spec;            // the metric ranked (rmse+nis, rmse+anis: rmse)
  bool with_nis = false;      // rmse+nis
  bool with_log_nis = false;  // rmse+anis
  // Smaller is better (metrics.h badness); NaN when the run cannot be judged. rmse+nis without a
  // scale group to set: RMSE · (1 + (ln NIS mean)²), the penalty of an inconsistent NIS;
  // rmse+anis: RMSE + |ln NIS mean| (NIS mean is NIS / dof).
  double badness(const Metrics& m) const;
  bool combined() const { return with_nis || with_log_nis; }
  // Ranks by the innovations alone (nll, nis_mean, …: a consistency metric), so coloured
  // innovations mislead it; an objective that reads truth (rmse, a scenario's error) does not.
  bool truth_free() const { return !combined() && spec.group == MetricGroup::kConsistency; }
};

// Any metric key of the scenario with a direction ("nis" is short for nis_mean), or a combined
// objective (rmse+nis, rmse+anis).
Expected<TuneObjective> make_objective(const Scenario& s, const std::string& name,
                                       const RunResult* probe = nullptr);
// The names make_objective accepts (for "did you mean" and the dialog).
std::vector<std::string> objective_names(const Scenario& s, const RunResult* probe = nullptr);

struct SearchParam {
  std::string key;
  double lo = 0.0, hi = 1.0;
  bool log = false;         // search in log10 (variances)
  std::string scale_group;  // preset flag: scales together with the other selected members
};

// One dataset of a tuning set: a log, or the dataset one simulator seed gives (`tune --seeds`),
// aggregated alike.
struct TuneLog {
  std::string name;  // the path, or "seed 7"
  const Dataset* data = nullptr;
  // Values this log is always run with, over the searched ones ({"sim.seed": 7}: a mode that
  // re-simulates inside the run then draws the same seed as the dataset).
  ParamValues fixed;
};

struct TuneOptions {
  TuneMethod method = TuneMethod::kBobyqa;
  int budget = 400;   // evaluations (each runs every log)
  double tol = 1e-6;  // stop when a step improves the objective by less than this fraction
  Aggregate aggregate = Aggregate::kMean;
  int threads = 0;  // 0: every core
  const std::atomic<bool>* cancel = nullptr;
  // Called from worker threads with the evaluations so far and the best objective.
  std::function<void(int evaluations, double best)> progress;
};

// What the scale check found for one scale group.
struct ScaleReport {
  std::string group;
  std::vector<std::string> keys;
  bool determined = true;  // the objective changes when every key scales together
  double change = 0.0;     // largest relative change of the objective over a ×10 and ÷10 scaling
  double shape_change = 0.0;    // its relative change when the first key alone moves as far
  bool by_consistency = false;  // the scale was set so that NIS mean / dof = 1
  double factor = 1.0;          // that scale relative to the shape's start
  double nis_mean = 0.0;        // NIS mean / dof at the result (mean over the logs)
  std::string note;             // why the scale could not be set, when it could not
};

struct LogReport {
  std::string name;
  Metrics metrics;     // of the best values on this log
  double value = 0.0;  // the objective's metric on this log (NaN when undefined)
};

// A consistency target (rmse+nis, rmse+anis) can cost the metric it ranks: a filter whose models
// cannot match the data reaches NIS mean / dof = 1 only by being a worse filter (issue 28: tuning
// radome's IMM for rmse+nis made every figure the paper reports worse). The metric and NIS mean /
// dof at the start and at the result, aggregated as the objective is.
struct TradeOff {
  std::string metric;  // "rmse"
  Direction direction = Direction::kLower;
  double start_value = 0.0, best_value = 0.0;
  double start_nis = 0.0, best_nis = 0.0;
  // The result's metric is more than 10 % worse than the start's: the user should choose.
  bool costly() const;
  double cost() const;  // the relative change of the metric for the worse (0.23: 23 %)
  std::string message() const;
};

struct TuneResult {
  ParamValues best;
  double objective = 0.0;  // aggregate badness of the best values
  double value = 0.0;      // the aggregated metric (mean, or the worst log's)
  Metrics metrics;         // of the first log's best run
  std::vector<LogReport> logs;
  std::vector<ScaleReport> scales;
  std::vector<std::string> at_bound;  // keys whose optimum sits on a search bound
  std::optional<TradeOff> trade_off;  // a combined objective: what consistency cost
  std::string method;                 // what ran ("bobyqa", "direct+bobyqa", ...)
  int evaluations = 0;
  bool cancelled = false;
};

// One key of a preset as a search parameter: bounds from the preset's range (else the table's),
// log10 space for a log scale, its scale group. Unknown, non-tunable or non-continuous keys are
// errors naming the key and the tunable ones.
Expected<SearchParam> search_param(const Preset& preset, const std::string& key);
// The preset's tunable keys (the default selection of Tune and `kfw-cli tune`). A model file
// that marks none is tuned over the parameters of its Q and R (engine/model/model_scenario.h).
std::vector<SearchParam> default_search(const Preset& preset);
// Why default_search is empty, and what to add to the file.
std::string no_tunable_message(const Preset& preset);
// The objective a tuning uses when none is asked for, and why (what `tune` reports):
//   the preset's own `default_objective`, when it declares one; else
//   rmse+nis   with truth, NIS and a scale group of two or more selected keys;
//   rmse+anis  with truth and NIS but no such group: RMSE + |ln(NIS mean / dof)|, so that an
//              RMSE-optimal but inconsistent filter (NIS mean / dof 0.4, say) is not chosen;
//   rmse       with truth and no innovations;
//   nll        without truth: the mean innovation NLL over all channels.
struct DefaultObjective {
  std::string name;
  std::string why;  // "truth, no scale group: ..."
};
DefaultObjective default_objective(const Preset& preset, const RunResult& probe,
                                   const std::vector<SearchParam>& params);

// Searches `params` (others held at `start`) over every log. Errors: no parameter, unknown or
// non-continuous keys, bad bounds (exit 2); no finite objective anywhere (exit 1).
Expected<TuneResult> tune(const Scenario& s, const std::vector<TuneLog>& logs,
                          const ParamValues& start, const std::vector<SearchParam>& params,
                          const TuneObjective& objective, const TuneOptions& options = {});

}  // namespace kfw
