#include "model/model_derived.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>

#include "core/statistics.h"
#include "model/model_reader.h"
#include "model/model_result.h"

namespace kfw::model {

using nlohmann::json;

namespace {

constexpr const char* kDerivedWhat = "";

// Truth columns as symbols of derived quantities (names that are free identifiers only).
void add_truth_symbols(ModelSpec& m) {
  m.truth_slots.assign(m.states.size(), -1);
  for (std::size_t i = 0; i < m.truth.size(); ++i) {
    const std::string& col = m.truth[i];
    if (col.empty() || !is_identifier(col) || is_reserved_name(col) || m.symbols.find(col) >= 0) {
      continue;
    }
    m.truth_slots[i] = m.symbols.add(col, kTruthSymbol);
  }
  // The channels' roles (their columns as read): a measurement minus the truth is an error. A
  // pre-processed channel's are its components (ModelResult::z holds what the filter compared).
  for (const auto& c : m.channels) {
    for (const auto& r : c.comps) {
      const bool free =
          is_identifier(r.name) && !is_reserved_name(r.name) && m.symbols.find(r.name) < 0;
      m.measured_slots.push_back(free ? m.symbols.add(r.name, kMeasuredSymbol) : -1);
    }
  }
}

Expected<DerivedSpec> parse_one(const detail::Reader& p, const std::string& name, const json& j,
                                const ModelSpec& m) {
  const std::string key = "model.derived." + name;
  DerivedSpec d;
  d.name = name;
  d.label = name;
  const json* text = &j;
  if (j.is_object()) {
    if (auto st = p.only_keys(j, key, {"expression", "label", "unit", "description"}); !st) {
      return st.err();
    }
    if (!j.contains("expression")) return p.error(key, "missing key 'expression'");
    text = &j.at("expression");
    for (auto [k, out] : {std::pair{"label", &d.label}, std::pair{"unit", &d.unit},
                          std::pair{"description", &d.description}}) {
      auto v = p.string(j, k, key, false, *out);
      if (!v) return v.err();
      *out = *v;
    }
  }
  auto e = p.expr(*text, j.is_object() ? key + ".expression" : key,
                  kAllSymbols | kTruthSymbol | kMeasuredSymbol, kDerivedWhat);
  if (!e) return e.err();
  d.e = *e;
  for (int slot : m.grid_param_slots) {
    const auto used = symbols_used(d.e.text, m.symbols);
    d.grid = d.grid || std::find(used.begin(), used.end(), slot) != used.end();
  }
  return d;
}

double finite_max_abs(const std::vector<double>& v) {
  double m = -1.0;
  for (double x : v) {
    if (std::isfinite(x)) m = std::max(m, std::fabs(x));
  }
  return m;
}

}  // namespace

Status parse_derived(const detail::Reader& p, const json& block, ModelSpec& m) {
  if (!block.is_object()) {
    return p.error("model.derived", "expected {\"NAME\": {\"expression\": ...}, ...}");
  }
  add_truth_symbols(m);
  for (auto it = block.begin(); it != block.end(); ++it) {
    if (!is_identifier(it.key())) {
      return p.error("model.derived." + it.key(), "a name (letters, digits and _)");
    }
    auto d = parse_one(p, it.key(), it.value(), m);
    if (!d) return d.err();
    m.derived.push_back(std::move(*d));
  }
  return Ok{};
}

std::vector<MetricSpec> derived_metric_specs(const ModelSpec& spec) {
  std::vector<MetricSpec> out;
  for (const auto& d : spec.derived) {
    const std::string about = d.description.empty() ? "derived quantity " + d.name : d.description;
    if (!d.series()) {
      out.push_back(
          {"derived." + d.name, d.label, d.unit, about, MetricGroup::kScenario, Direction::kNone});
      continue;
    }
    out.push_back({"derived." + d.name + ".rms", d.label + ", RMS over the run", d.unit, about,
                   MetricGroup::kScenario, Direction::kNone});
    out.push_back({"derived." + d.name + ".max", d.label + ", largest magnitude", d.unit, about,
                   MetricGroup::kScenario, Direction::kNone});
  }
  return out;
}

DerivedScalars::DerivedScalars(const ModelSpec& spec)
    : spec_(spec), vars_(spec.symbols.names.size(), 0.0), out_(spec.derived.size(), 0.0) {
  for (std::size_t q = 0; q < spec.derived.size(); ++q) {
    if (!spec.derived[q].series()) group_.add(spec.derived[q].e.text, &out_[q]);
  }
  ok_ = !group_.empty() && group_.bind(spec.symbols, vars_.data()).ok();
}

Metrics DerivedScalars::eval(const ParamValues& values, double dt) {
  Metrics out;
  if (!ok_) return out;
  for (std::size_t i = 0; i < spec_.param_slots.size(); ++i)
    vars_[static_cast<std::size_t>(spec_.param_slots[i])] = param(values, spec_.param_keys[i]);
  vars_[static_cast<std::size_t>(spec_.dt_slot)] = dt;
  group_.eval();
  for (std::size_t q = 0; q < spec_.derived.size(); ++q) {
    const DerivedSpec& d = spec_.derived[q];
    if (!d.series() && std::isfinite(out_[q])) out["derived." + d.name] = out_[q];
  }
  return out;
}

namespace {

// What a run's derived series read besides the estimates: the parameters and dt (vars at those
// slots), t, the truth columns, the inputs and the measurements. A run compares its own columns
// in place (ReadsView); only a run that misses copies them into the cache (Reads).
struct ReadsView {
  std::vector<double> values;
  std::vector<const std::vector<double>*> columns;
};
struct Reads {
  std::vector<double> values;
  std::vector<std::vector<double>> columns;
};

// Bit for bit (a missing sample is NaN, which == would call different from itself).
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

bool same_reads(const Reads& kept, const ReadsView& now) {
  if (!same_bits(kept.values, now.values) || kept.columns.size() != now.columns.size()) {
    return false;
  }
  for (std::size_t i = 0; i < now.columns.size(); ++i) {
    if (!same_bits(kept.columns[i], *now.columns[i])) return false;
  }
  return true;
}

Reads copy_of(const ReadsView& now) {
  Reads k{now.values, {}};
  for (const auto* c : now.columns)
    k.columns.push_back(*c);
  return k;
}

// A pre-processed channel's columns as read (its roles' symbols), from the data.
using RawColumns = std::vector<std::pair<int, const std::vector<double>*>>;

ReadsView reads_of(const ModelSpec& spec, const std::vector<int>& slots,
                   const std::vector<double>& vars, const ModelResult& r,
                   const std::vector<const std::vector<double>*>& inputs, const RawColumns& raw) {
  static const std::vector<double> kNone;
  ReadsView k;
  for (int slot : slots)  // the symbols the series name: parameters, dt (the rest are per row)
    k.values.push_back(vars[static_cast<std::size_t>(slot)]);
  k.columns.push_back(&r.t);
  for (const auto& c : r.truth)
    k.columns.push_back(&c);
  for (const auto* c : inputs)
    k.columns.push_back(c ? c : &kNone);
  for (std::size_t j = 0; j < spec.measured_slots.size() && j < r.z.size(); ++j) {
    if (spec.measured_slots[j] >= 0) k.columns.push_back(&r.z[j]);
  }
  for (const auto& [slot, col] : raw)
    k.columns.push_back(col);
  return k;
}

// Sets row k's symbols of the series: t, states, truth, inputs, measurements.
void set_row(const ModelSpec& spec, const ModelResult& r,
             const std::vector<const std::vector<double>*>& inputs, const RawColumns& raw,
             std::size_t k, std::vector<double>& vars) {
  for (const auto& [slot, col] : raw)
    vars[static_cast<std::size_t>(slot)] = (*col)[k];
  vars[static_cast<std::size_t>(spec.t_slot)] = r.t[k];
  for (std::size_t i = 0; i < spec.states.size(); ++i) {
    vars[static_cast<std::size_t>(spec.state_slots[i])] = r.x[i][k];
    if (spec.truth_slots.size() > i && spec.truth_slots[i] >= 0) {
      vars[static_cast<std::size_t>(spec.truth_slots[i])] =
          r.truth[i].empty() ? kNoSample : r.truth[i][k];
    }
  }
  for (std::size_t i = 0; i < spec.inputs.size(); ++i) {
    vars[static_cast<std::size_t>(spec.input_slots[i])] =
        inputs[i] && k < inputs[i]->size() ? (*inputs[i])[k] : kNoSample;
  }
  for (std::size_t j = 0; j < spec.measured_slots.size() && j < r.z.size(); ++j) {
    if (spec.measured_slots[j] >= 0)
      vars[static_cast<std::size_t>(spec.measured_slots[j])] = r.z[j][k];
  }
  if (!r.imm) return;
  for (std::size_t a = 0; a < spec.grid_param_slots.size() && a < r.imm->axes.size(); ++a) {
    const auto& axis = r.imm->axes[a];
    if (spec.grid_param_slots[a] >= 0)
      vars[static_cast<std::size_t>(spec.grid_param_slots[a])] = axis.estimate[k];
    if (a < spec.grid_truth_slots.size() && spec.grid_truth_slots[a] >= 0)
      vars[static_cast<std::size_t>(spec.grid_truth_slots[a])] =
          axis.truth.empty() ? kNoSample : axis.truth[k];
  }
}

// derived.NAME.rms and .max of each series.
void series_metrics(const ModelSpec& spec, ModelResult& r) {
  std::size_t s = 0;
  for (const auto& ds : spec.derived) {
    if (!ds.series()) continue;
    const std::vector<double>& v = r.derived[s++];
    const double top = finite_max_abs(v);
    if (top < 0.0) {
      r.undefined["derived." + ds.name + ".rms"] = "no finite value in the run";
      r.undefined["derived." + ds.name + ".max"] = "no finite value in the run";
      continue;
    }
    const std::vector<double> zero(v.size(), 0.0);
    r.metrics["derived." + ds.name + ".rms"] = rmse_finite(v, zero);
    r.metrics["derived." + ds.name + ".max"] = top;
  }
}

}  // namespace

struct DerivedCache::Entry {
  Reads reads;
  std::vector<std::vector<double>> series;  // the series that read no estimate, in order
};

DerivedCache::DerivedCache() = default;
DerivedCache::~DerivedCache() = default;

Status add_derived(const ModelSpec& spec, const ParamValues& values, const Dataset& d,
                   ModelResult& r, DerivedCache* cache) {
  if (spec.derived.empty()) return Ok{};
  std::vector<double> vars(spec.symbols.names.size(), 0.0);
  for (std::size_t i = 0; i < spec.param_slots.size(); ++i)
    vars[static_cast<std::size_t>(spec.param_slots[i])] = param(values, spec.param_keys[i]);
  vars[static_cast<std::size_t>(spec.dt_slot)] =
      d.rows() >= 2 ? d.median_dt() : param(values, spec.sim_dt_key);
  std::vector<double> out(spec.derived.size(), 0.0);
  // Series that read the estimates (live) and those that do not (fixed: the same for the same
  // data and parameters, kept in the cache between runs).
  ExprGroup scalars, live, fixed;
  std::vector<std::size_t> fixed_rows;  // index into r.derived of each fixed series
  for (std::size_t q = 0; q < spec.derived.size(); ++q) {
    const DerivedSpec& ds = spec.derived[q];
    if (!ds.series()) {
      scalars.add(ds.e.text, &out[q]);
      continue;
    }
    if (ds.live()) {
      live.add(ds.e.text, &out[q]);
    } else {
      fixed_rows.push_back(r.derived.size());
      fixed.add(ds.e.text, &out[q]);
    }
    r.derived_names.push_back(ds.name);
    r.derived.emplace_back(r.steps(), kNoSample);
  }
  for (ExprGroup* g : {&scalars, &live, &fixed}) {
    if (auto st = g->bind(spec.symbols, vars.data()); !st) return st;
  }
  scalars.eval();
  for (std::size_t q = 0; q < spec.derived.size(); ++q) {
    const DerivedSpec& ds = spec.derived[q];
    if (ds.series()) continue;
    if (std::isfinite(out[q])) {
      r.metrics["derived." + ds.name] = out[q];
    } else {
      r.undefined["derived." + ds.name] = "not finite at the run's values";
    }
  }
  if (r.derived.empty()) return Ok{};
  // The inputs' columns, looked up once (null: not in the data).
  std::vector<const std::vector<double>*> inputs(spec.inputs.size(), nullptr);
  for (std::size_t i = 0; i < spec.inputs.size(); ++i) {
    if (d.has(spec.inputs[i].name)) inputs[i] = &d.col(spec.inputs[i].name);
  }
  RawColumns raw;
  for (const auto& c : spec.channels) {
    for (std::size_t i = 0; i < c.column_slots.size(); ++i) {
      if (d.has(c.roles[i].name)) raw.emplace_back(c.column_slots[i], &d.col(c.roles[i].name));
    }
  }
  // A closed loop's columns (its reference, outputs, noise-free responses); NaN on a log.
  const std::vector<double> none(r.steps(), kNoSample);
  for (const auto& [slot, col] : spec.loop_columns)
    raw.emplace_back(slot, d.has(col) && d.col(col).size() >= r.steps() ? &d.col(col) : &none);
  ReadsView reads;
  bool hit = false;
  if (cache && !fixed.empty()) {
    std::vector<int> slots;
    for (const auto& ds : spec.derived) {
      if (!ds.series() || ds.live()) continue;
      for (int slot : symbols_used(ds.e.text, spec.symbols))
        slots.push_back(slot);
    }
    reads = reads_of(spec, slots, vars, r, inputs, raw);
    std::lock_guard lock(cache->mu);
    if (cache->entry && same_reads(cache->entry->reads, reads)) {
      hit = true;
      for (std::size_t i = 0; i < fixed_rows.size(); ++i)
        r.derived[fixed_rows[i]] = cache->entry->series[i];
    }
  }
  // Per r.derived entry: its spec.derived index, and whether this run evaluates it.
  std::vector<std::size_t> series_q;
  std::vector<bool> evaluate;
  for (std::size_t q = 0; q < spec.derived.size(); ++q) {
    if (!spec.derived[q].series()) continue;
    series_q.push_back(q);
    evaluate.push_back(!hit || spec.derived[q].live());
  }
  for (std::size_t k = 0; k < r.steps(); ++k) {
    set_row(spec, r, inputs, raw, k, vars);
    live.eval();
    if (!hit) fixed.eval();
    for (std::size_t s = 0; s < series_q.size(); ++s) {
      if (evaluate[s]) r.derived[s][k] = out[series_q[s]];
    }
  }
  if (cache && !fixed.empty() && !hit) {
    auto e = std::make_unique<DerivedCache::Entry>();
    e->reads = copy_of(reads);
    for (std::size_t i : fixed_rows)
      e->series.push_back(r.derived[i]);
    std::lock_guard lock(cache->mu);
    cache->entry = std::move(e);
  }
  series_metrics(spec, r);
  return Ok{};
}

}  // namespace kfw::model
