// Derived quantities of a model file (version 2, issue 27): named expressions computed from a
// run. One of parameters and dt only is a scalar per run — the metric derived.NAME, at the data's
// median dt (or sim.dt) — such as seed 000's tracking index β. One that uses states (the
// estimates), truth columns, t or inputs is a series per run — a column derived.NAME of the
// run's table, with the metrics derived.NAME.rms and derived.NAME.max (largest magnitude).
#pragma once

#include <memory>
#include <mutex>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/metrics.h"
#include "core/param_spec.h"
#include "model/model_spec.h"

namespace kfw::model {

struct ModelResult;

namespace detail {
class Reader;
}

// Adds each truth column whose name is a free identifier as a symbol (kTruthSymbol), then parses
// "derived": {"NAME": {"expression", "label", "unit", "description"}} (or "NAME": "expression").
Status parse_derived(const detail::Reader& p, const nlohmann::json& block, ModelSpec& m);

// The metrics the derived quantities declare.
std::vector<MetricSpec> derived_metric_specs(const ModelSpec& spec);

// The scalar derived quantities (parameters and dt only), compiled once: eval() gives them at
// `dt` as metrics derived.NAME (one that is not finite is left out). One evaluator per thread.
class DerivedScalars {
 public:
  explicit DerivedScalars(const ModelSpec& spec);
  Metrics eval(const ParamValues& values, double dt);

 private:
  const ModelSpec& spec_;
  std::vector<double> vars_, out_;
  ExprGroup group_;
  bool ok_ = false;
};

// The series of the last run that read no estimate (a range error of the data against truth),
// with copies of everything they read: a run on the same data at the same parameters takes them
// instead of evaluating them again (seed 004: 5 of its 6 series, ≈ 6 ms of a 35 ms run). One per
// scenario; runs on several threads share it.
struct DerivedCache {
  DerivedCache();
  ~DerivedCache();
  struct Entry;
  std::mutex mu;
  std::unique_ptr<Entry> entry;
};

// Evaluates every derived quantity on a finished run: series into r.derived, metrics into
// r.metrics (a value that is not finite goes to r.undefined with the reason). `cache`: see
// DerivedCache (null: none).
Status add_derived(const ModelSpec& spec, const ParamValues& values, const Dataset& d,
                   ModelResult& r, DerivedCache* cache = nullptr);

}  // namespace kfw::model
