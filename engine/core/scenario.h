// A scenario is the unit of extension: its parameter table, its dataset schema, its simulator and
// its runner. Since issue 30 every scenario is built from a model file (engine/model registers
// "model" with the registry below).
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/metrics.h"
#include "core/param_spec.h"

namespace kfw {

// One measurement channel's innovations, for consistency checks that work for every scenario.
struct InnovationChannel {
  std::string name;                // identifier: "angle", "range_1", "position" (metric keys)
  std::string label;               // display name ("range 1"); empty: the name
  double dof = 1.0;                // measurement dimension
  std::vector<double> nis;         // per step; NaN where the channel did not update
  std::vector<double> normalized;  // y/√S per step (scalar channels; empty otherwise)
  std::vector<double> log_det_s;   // log det S per step, for the NLL (empty: not reported)
  // The NLL's term per step where it is not ½(dof log 2π + log det S + NIS): an IMM's −log c,
  // the mixture's (NaN where none); empty: from log_det_s.
  std::vector<double> nll;
  // A channel of several components: each component (its role) with y_j/√S_jj per step, tested
  // for whiteness one by one (whiteness_p.<channel>.<role>); empty for a scalar channel.
  struct Component {
    std::string name;
    std::vector<double> normalized;
  };
  std::vector<Component> components;
  const std::string& display() const { return label.empty() ? name : label; }
};

// One estimated state over the run: what rmse.<state>, the finiteness check and generic plots
// read. Pointers into the result's own arrays (valid while the result lives).
struct StateSeries {
  std::string key;    // identifier: "theta", "x"
  std::string label;  // "θ (angle)"
  std::string unit;   // "deg"
  const std::vector<double>* estimate = nullptr;
  const std::vector<double>* variance = nullptr;  // may be null
  const std::vector<double>* truth = nullptr;     // may be null (no truth)
};

// NEES against truth, when the dataset has truth.
struct NeesSeries {
  double dof = 1.0;
  std::vector<double> nees;  // per step; NaN where unknown
  // Some step has a truth value for every state of the NEES: a NEES undefined everywhere then
  // means a singular covariance (a noise-free sensor), not a missing truth column.
  bool truth = false;
  // At some step with truth, the error x̂ − x of every state has a finite square: when not, a
  // NEES undefined everywhere means the estimate overflowed, not a singular covariance.
  bool error_finite = true;
};

// The per-step arrays of one run plus its metrics. Each scenario derives its own result with the
// arrays its plots need; plots read from it and nothing reaches back into a filter object.
struct RunResult {
  virtual ~RunResult() = default;
  std::vector<double> t;              // time of each step, s
  Metrics metrics;                    // finite values only (see finalize_run)
  UndefinedMetrics undefined;         // metrics undefined for this run, with the reason
  std::vector<std::string> warnings;  // numerical trouble recorded during the run, shown to users
  // The innovation channels' names, labels and dof without their arrays (finalize_run fills it;
  // describe_metric reads it, so the metrics table does not recompute every channel).
  std::vector<InnovationChannel> channel_names;
  std::size_t steps() const { return t.size(); }
  // Per-step output as a CSV table (estimates, covariance diagonal, innovations, ...).
  virtual Dataset table() const = 0;
  // The same columns without copying them, for a streamed write (valid while this result lives);
  // the default copies table() once.
  virtual std::vector<TableColumn> table_view() const;
  // The innovation channels and the NEES, for the consistency panel (empty: none offered).
  virtual std::vector<InnovationChannel> channels() const { return {}; }
  virtual NeesSeries nees_series() const { return {}; }
  // The estimated states (empty: the scenario reports its accuracy metrics itself).
  virtual std::vector<StateSeries> states() const { return {}; }
};

// A column whose noise sets a parameter: the generic `kfw-cli noise` (filter/noise_estimate.h)
// reads each column's white-noise variance v from the high-frequency part of its PSD (seed 000,
// eq. 3) and proposes the parameter's value. A scenario declares its links once
// (Scenario::noise_links; a model file with "noise_param") and every surface reads them.
struct NoiseLink {
  std::vector<std::string> columns;  // an input or a measurement role (several: one parameter
                                     // for a channel's roles)
  std::string param;                 // the parameter key the noise sets
  std::string declared;              // where it is declared, for messages; empty: in code
  // The parameter's value for the columns' variances v (one per column, in their order), the
  // other parameters at `p`, `dt_s` the data's median interval. It may lie outside the
  // parameter's range (the command clamps it and says so); an Error when no value gives v.
  std::function<Expected<double>(const std::vector<double>& v, const ParamValues& p, double dt_s)>
      value;
};
// The column's noise variance is the parameter itself (seed 000: Q = N_ω, R = N_θ).
NoiseLink noise_variance_link(std::string column, std::string param);

// Lets a long run be cancelled and report progress; both may be empty.
struct RunControl {
  const std::atomic<bool>* cancel = nullptr;
  std::function<void(double)> progress;
  bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
};

class Scenario {
 public:
  virtual ~Scenario() = default;
  virtual std::string name() const = 0;   // "helicopter"
  virtual std::string title() const = 0;  // "Helicopter attitude: indirect KF (seed 000)"
  virtual const ParamTable& params() const = 0;
  virtual std::vector<ColumnSpec> columns() const = 0;

  // A reproducible synthetic dataset from the `sim.*` parameters (seeded by `sim.seed`).
  virtual Expected<Dataset> simulate(const ParamValues& p) const = 0;
  // This scenario with the simulator's initial state drawn from the filter's prior N(x̂0, P0)
  // (preset `"sim": {"x0_from_prior": true}`), so that a matched model passes the NEES test;
  // null when the scenario cannot do it.
  virtual std::shared_ptr<const Scenario> with_x0_from_prior() const { return nullptr; }
  // Filters a dataset. Bad parameters or a dataset missing columns come back as an Error (exit
  // code 2); a run that breaks down numerically as a failure naming the step and time (exit 1).
  // Runs run_impl, then finalize_run: metrics shared by every scenario, non-finite metrics moved
  // to `undefined`, and the estimates checked finite.
  Expected<std::shared_ptr<const RunResult>> run(const Dataset& d, const ParamValues& p,
                                                 const RunControl& control = {}) const;

  // The state whose RMSE is `rmse` (a key of RunResult::states()); empty when the scenario
  // sets `rmse` itself (a compound such as the 3-D position).
  virtual std::string primary_state() const { return {}; }
  // The scenario's own metrics (the shared vocabulary is declared in metrics.h).
  virtual std::vector<MetricSpec> metric_specs() const { return {}; }
  // Steady-state gains for the current parameters (closed form and DARE), when the scenario has
  // any. With a dataset, its sample period is used; without, the simulator's.
  virtual Expected<Metrics> gain(const ParamValues& p, const Dataset* data = nullptr) const;

  // When a run with these values does not filter a loaded dataset (a mode that re-simulates):
  // why, and the assignment that makes runs use it ("mode=replay"). Empty: the data are used.
  struct DataUnused {
    std::string why, fix;
  };
  virtual std::optional<DataUnused> data_unused(const ParamValues&) const { return std::nullopt; }

  // The columns whose noise sets a parameter, for `kfw-cli noise` (empty: none).
  virtual std::vector<NoiseLink> noise_links() const { return {}; }

  // Scenario-specific analyses offered on the command line as
  // `kfw-cli NAME SCENARIO|PRESET [--data FILE] [--set k=v]...` (e.g. underwater "stats").
  virtual std::vector<std::string> commands() const { return {}; }
  // Runs one of commands() on a dataset; returns the JSON text to print.
  virtual Expected<std::string> command(const std::string& name, const Dataset& d,
                                        const ParamValues& p) const;

 protected:
  virtual Expected<std::shared_ptr<RunResult>> run_impl(const Dataset& d, const ParamValues& p,
                                                        const RunControl& control) const = 0;
};

// The shared metrics every run gets (rmse.<state>, rmse from the primary state), non-finite
// metrics moved to `undefined` with a reason, and a failure (exit 1) naming the first step at
// which an estimate or its variance stopped being finite.
Status finalize_run(RunResult& r, const Scenario& s, bool check_finite = true);

// The spec of a metric key for this scenario: shared (exact or pattern), else the scenario's.
// A key declared nowhere gets a plain spec (label = key, group scenario, lower is better).
// With a result, pattern targets are filled in (nis_mean.<channel>: that channel's dof).
MetricSpec describe_metric(const Scenario& s, std::string_view key, const RunResult* r = nullptr);
// True when the key is declared (shared, pattern, or by the scenario).
bool is_declared_metric(const Scenario& s, std::string_view key);
// Every metric key that a scenario can produce, for "did you mean" (with a result: its keys too).
std::vector<std::string> metric_keys(const Scenario& s, const RunResult* r = nullptr);
// The flat metrics JSON: {"rmse": 1.6, ..., "undefined": {"nees_mean": "no truth column"}}.
std::string metrics_to_json(const Metrics& m, const UndefinedMetrics& undefined, int indent = 2);

// Scenarios are built from the preset file itself (since issue 30 every system is a model file,
// "scenario": "model"; the compiled built-ins are gone, their names retired, core/retired.h).
class ScenarioRegistry {
 public:
  // Reads the whole preset, its keys in the file's order; errors name the file (`path`) and key.
  using PresetFactory = std::function<Expected<std::unique_ptr<Scenario>>(
      const nlohmann::ordered_json& preset, const std::string& path)>;
  void add_from_preset(std::string name, PresetFactory factory);
  // The factory of a scenario built from its preset, or nullptr.
  const PresetFactory* from_preset(const std::string& name) const;
  // The names a preset's "scenario" may give ("model"), for "did you mean".
  std::vector<std::string> names() const;

 private:
  std::map<std::string, PresetFactory> preset_factories_;
};

// The model engine (engine/model), registered through the list engine/CMakeLists.txt generates.
const ScenarioRegistry& scenarios();
// "unknown scenario 'x' (…)" for a preset's scenario that no factory builds.
std::string unknown_scenario(const std::string& name);

// True when a key belongs to the simulator (changing it needs a new simulated dataset).
inline bool is_sim_key(const std::string& key) {
  return key.rfind("sim.", 0) == 0;
}

}  // namespace kfw
