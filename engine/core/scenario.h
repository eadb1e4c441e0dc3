// A scenario is the unit of extension: its parameter table, its dataset schema, its simulator and
// its runner. Each lives in engine/scenarios/<name>/ and registers itself by name.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/param_spec.h"

namespace kfw {

// Summary numbers of a run: a flat, ordered map (the CLI writes it as a JSON object of numbers).
using Metrics = std::map<std::string, double>;

// One measurement channel's innovations, for consistency checks that work for every scenario.
struct InnovationChannel {
  std::string name;                // "angle", "range 1", "position", ...
  double dof = 1.0;                // measurement dimension
  std::vector<double> nis;         // per step; NaN where the channel did not update
  std::vector<double> normalized;  // y/√S per step (scalar channels; empty otherwise)
};

// NEES against truth, when the dataset has truth.
struct NeesSeries {
  double dof = 1.0;
  std::vector<double> nees;  // per step; NaN where unknown
};

// The per-step arrays of one run plus its metrics. Each scenario derives its own result with the
// arrays its plots need; plots read from it and nothing reaches back into a filter object.
struct RunResult {
  virtual ~RunResult() = default;
  std::vector<double> t;  // time of each step, s
  Metrics metrics;
  std::vector<std::string> warnings;  // numerical trouble recorded during the run, shown to users
  std::size_t steps() const { return t.size(); }
  // Per-step output as a CSV table (estimates, covariance diagonal, innovations, ...).
  virtual Dataset table() const = 0;
  // The innovation channels and the NEES, for the consistency panel (empty: none offered).
  virtual std::vector<InnovationChannel> channels() const { return {}; }
  virtual NeesSeries nees_series() const { return {}; }
};

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
  // Filters a dataset. Bad parameters or a dataset missing columns come back as an Error.
  virtual Expected<std::shared_ptr<const RunResult>> run(const Dataset& d, const ParamValues& p,
                                                         const RunControl& control = {}) const = 0;
  // Steady-state gains for the current parameters (closed form and DARE), when the scenario has
  // any. With a dataset, its sample period is used; without, the simulator's.
  virtual Expected<Metrics> gain(const ParamValues& p, const Dataset* data = nullptr) const;

  // Scenario-specific analyses offered on the command line as
  // `kfw-cli NAME SCENARIO|PRESET [--data FILE] [--set k=v]...` (e.g. underwater "stats").
  virtual std::vector<std::string> commands() const { return {}; }
  // Runs one of commands() on a dataset; returns the JSON text to print.
  virtual Expected<std::string> command(const std::string& name, const Dataset& d,
                                        const ParamValues& p) const;
};

class ScenarioRegistry {
 public:
  using Factory = std::function<std::unique_ptr<Scenario>()>;
  void add(std::string name, Factory factory);
  std::vector<std::string> names() const;
  // A new scenario object, or nullptr for an unknown name.
  std::unique_ptr<Scenario> make(const std::string& name) const;

 private:
  std::map<std::string, Factory> factories_;
};

// Every scenario compiled in (engine/scenarios/*), registered once.
const ScenarioRegistry& scenarios();
Expected<std::unique_ptr<Scenario>> make_scenario(const std::string& name);

// True when a key belongs to the simulator (changing it needs a new simulated dataset).
inline bool is_sim_key(const std::string& key) {
  return key.rfind("sim.", 0) == 0;
}

}  // namespace kfw
