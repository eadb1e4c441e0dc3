#include "model/model_derived.h"

#include <cmath>
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
  // The channels' roles (their columns as read): a measurement minus the truth is an error.
  for (const auto& c : m.channels) {
    for (const auto& r : c.roles) {
      const bool free =
          is_identifier(r.name) && !is_reserved_name(r.name) && m.symbols.find(r.name) < 0;
      m.measured_slots.push_back(free ? m.symbols.add(r.name, kMeasuredSymbol) : -1);
    }
  }
}

Expected<DerivedSpec> parse_one(const detail::Reader& p, const std::string& name, const json& j) {
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
    auto d = parse_one(p, it.key(), it.value());
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

Status add_derived(const ModelSpec& spec, const ParamValues& values, const Dataset& d,
                   ModelResult& r) {
  if (spec.derived.empty()) return Ok{};
  std::vector<double> vars(spec.symbols.names.size(), 0.0);
  for (std::size_t i = 0; i < spec.param_slots.size(); ++i)
    vars[static_cast<std::size_t>(spec.param_slots[i])] = param(values, spec.param_keys[i]);
  vars[static_cast<std::size_t>(spec.dt_slot)] =
      d.rows() >= 2 ? d.median_dt() : param(values, spec.sim_dt_key);
  std::vector<double> out(spec.derived.size(), 0.0);
  ExprGroup scalars, series;
  for (std::size_t q = 0; q < spec.derived.size(); ++q)
    (spec.derived[q].series() ? series : scalars).add(spec.derived[q].e.text, &out[q]);
  if (auto st = scalars.bind(spec.symbols, vars.data()); !st) return st;
  if (auto st = series.bind(spec.symbols, vars.data()); !st) return st;
  scalars.eval();
  for (std::size_t q = 0; q < spec.derived.size(); ++q) {
    const DerivedSpec& ds = spec.derived[q];
    if (ds.series()) {
      r.derived_names.push_back(ds.name);
      r.derived.emplace_back(r.steps(), kNoSample);
    } else if (std::isfinite(out[q])) {
      r.metrics["derived." + ds.name] = out[q];
    } else {
      r.undefined["derived." + ds.name] = "not finite at the run's values";
    }
  }
  if (series.empty()) return Ok{};
  for (std::size_t k = 0; k < r.steps(); ++k) {
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
          d.has(spec.inputs[i].name) ? d.col(spec.inputs[i].name)[k] : kNoSample;
    }
    for (std::size_t j = 0; j < spec.measured_slots.size() && j < r.z.size(); ++j) {
      if (spec.measured_slots[j] >= 0)
        vars[static_cast<std::size_t>(spec.measured_slots[j])] = r.z[j][k];
    }
    series.eval();
    std::size_t s = 0;
    for (std::size_t q = 0; q < spec.derived.size(); ++q) {
      if (spec.derived[q].series()) r.derived[s++][k] = out[q];
    }
  }
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
  return Ok{};
}

}  // namespace kfw::model
