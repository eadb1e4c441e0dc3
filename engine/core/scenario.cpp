#include "core/scenario.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "core/statistics.h"
#include "core/suggest.h"

namespace kfw {

void register_all_scenarios(ScenarioRegistry& registry);  // generated: scenario_list.cpp

std::vector<TableColumn> RunResult::table_view() const {
  auto d = std::make_shared<const Dataset>(table());
  std::vector<TableColumn> cols = table_columns(*d);
  for (auto& c : cols)
    c.keep = d;
  return cols;
}

Expected<Metrics> Scenario::gain(const ParamValues&, const Dataset*) const {
  return Error{"scenario '" + name() + "' has no steady-state gain"};
}

Expected<std::string> Scenario::command(const std::string& cmd, const Dataset&,
                                        const ParamValues&) const {
  return Error{"scenario '" + name() + "' has no command '" + cmd + "'"};
}

NoiseLink noise_variance_link(std::string column, std::string param) {
  NoiseLink l;
  l.columns = {std::move(column)};
  l.param = std::move(param);
  l.value = [](const std::vector<double>& v, const ParamValues&, double) -> Expected<double> {
    return v.front();
  };
  return l;
}

Expected<std::shared_ptr<const RunResult>> Scenario::run(const Dataset& d, const ParamValues& p,
                                                         const RunControl& control) const {
  auto r = run_impl(d, p, control);
  if (!r) return r.err();
  // A cancelled run is partial by design: its tail is not a breakdown.
  if (auto st = finalize_run(**r, *this, !control.cancelled()); !st) return st.err();
  return std::shared_ptr<const RunResult>(std::move(*r));
}

namespace {

std::string step_text(const RunResult& r, std::size_t k) {
  std::ostringstream os;
  os << "step " << k;
  if (k < r.t.size()) os << " (t = " << r.t[k] << " s)";
  return os.str();
}

// The first step at which a series that had been finite stops being so (an infinity anywhere
// counts); leading NaN is "not yet initialised" and allowed.
std::optional<std::size_t> first_breakdown(const std::vector<double>& v) {
  bool started = false;
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (std::isinf(v[k])) return k;
    if (std::isfinite(v[k])) {
      started = true;
    } else if (started) {
      return k;
    }
  }
  return std::nullopt;
}

bool matches_pattern(std::string_view pattern, std::string_view key) {
  const auto lt = pattern.find('<');
  if (lt == std::string_view::npos) return pattern == key;
  const std::string_view prefix = pattern.substr(0, lt);
  return key.size() > prefix.size() && key.substr(0, prefix.size()) == prefix;
}

std::string replace_placeholder(std::string text, std::string_view name) {
  for (auto p = text.find('<'); p != std::string::npos; p = text.find('<', p)) {
    const auto q = text.find('>', p);
    if (q == std::string::npos) break;
    text.replace(p, q - p + 1, name);
    p += name.size();
  }
  return text;
}

}  // namespace

Status finalize_run(RunResult& r, const Scenario& s, bool check_finite) {
  const auto states = r.states();
  for (const auto& st : states) {
    for (const auto* series : {st.estimate, st.variance}) {
      if (!check_finite) break;
      if (!series) continue;
      if (auto k = first_breakdown(*series)) {
        return failure(step_text(r, *k) + ": the estimate of '" + st.key + "'" +
                       (series == st.variance ? " has a non-finite variance" : " is not finite") +
                       "; the run stops here");
      }
    }
    if (st.variance && check_finite) {
      for (std::size_t k = 0; k < st.variance->size(); ++k) {
        if ((*st.variance)[k] < 0.0) {
          return failure(step_text(r, k) + ": the variance of '" + st.key +
                         "' is negative (the covariance lost definiteness)");
        }
      }
    }
    if (st.truth && st.estimate) {
      const std::string key = "rmse." + st.key;
      if (!r.metrics.count(key) && !r.undefined.count(key)) {  // kept: the scenario's own
        if (count_finite(*st.truth) == 0) {
          r.undefined.emplace(key, "no truth for '" + st.key + "' in the data");
        } else {
          r.metrics[key] = rmse_finite(*st.estimate, *st.truth);
        }
      }
    } else if (st.estimate && !r.metrics.count("rmse." + st.key)) {
      r.undefined.emplace("rmse." + st.key, "no truth for '" + st.key + "' in the data");
    }
  }
  const auto channels = check_finite ? r.channels() : std::vector<InnovationChannel>{};
  r.channel_names.clear();
  for (const auto& c : channels)
    r.channel_names.push_back({c.name, c.label, c.dof, {}, {}, {}, {}});
  for (const auto& c : channels) {
    for (std::size_t k = 0; k < c.nis.size(); ++k) {
      if (std::isinf(c.nis[k])) {
        return failure(step_text(r, k) + ": the NIS of channel '" + c.name +
                       "' is not finite (the innovation overflowed); the run stops here");
      }
    }
  }
  const std::string primary = s.primary_state();
  if (!primary.empty() && !r.metrics.count("rmse")) {
    auto it = r.metrics.find("rmse." + primary);
    if (it != r.metrics.end()) {
      r.metrics["rmse"] = it->second;
    } else {
      r.undefined.emplace("rmse", "no truth for the primary state '" + primary + "' in the data");
    }
  }
  for (auto it = r.metrics.begin(); it != r.metrics.end();) {
    if (std::isfinite(it->second)) {
      ++it;
      continue;
    }
    r.undefined.emplace(it->first, "no finite value in this run");
    it = r.metrics.erase(it);
  }
  for (const auto& [key, why] : r.undefined)
    r.metrics.erase(key);
  return Ok{};
}

MetricSpec describe_metric(const Scenario& s, std::string_view key, const RunResult* r) {
  for (const auto& spec : s.metric_specs()) {
    if (spec.key == key) return spec;
  }
  for (const auto& spec : shared_metric_specs()) {
    if (!matches_pattern(spec.key, key)) continue;
    MetricSpec out = spec;
    out.key = std::string(key);
    const auto lt = spec.key.find('<');
    if (lt == std::string::npos) {
      if (key == "rmse" && !s.primary_state().empty() && r) {
        for (const auto& st : r->states()) {
          if (st.key == s.primary_state()) {
            out.unit = st.unit;
            out.label = "RMSE of " + (st.label.empty() ? st.key : st.label);
          }
        }
      }
      return out;
    }
    const std::string_view name = key.substr(lt);
    std::string label(name);
    // Only the kind of series the pattern names is asked for: channels() copies every
    // channel's per-step arrays, and the metrics table calls this on every re-run.
    if (r && spec.key.find("<state>") != std::string::npos) {
      for (const auto& st : r->states()) {
        if (st.key == name) {
          if (!st.label.empty()) label = st.label;
          out.unit = st.unit;
        }
      }
    } else if (r) {
      std::vector<InnovationChannel> computed;  // a result finalize_run did not see
      if (r->channel_names.empty()) computed = r->channels();
      for (const auto& c : r->channel_names.empty() ? computed : r->channel_names) {
        if (c.name == name) {
          label = c.display();
          if (spec.key == "nis_mean.<channel>") out.target = c.dof;
        }
      }
    }
    out.label = replace_placeholder(spec.label, label);
    out.description = replace_placeholder(spec.description, label);
    return out;
  }
  MetricSpec plain;
  plain.key = std::string(key);
  plain.label = std::string(key);
  return plain;
}

bool is_declared_metric(const Scenario& s, std::string_view key) {
  for (const auto& spec : s.metric_specs()) {
    if (spec.key == key) return true;
  }
  for (const auto& spec : shared_metric_specs()) {
    if (matches_pattern(spec.key, key)) return true;
  }
  return false;
}

std::vector<std::string> metric_keys(const Scenario& s, const RunResult* r) {
  std::vector<std::string> keys;
  for (const auto& spec : shared_metric_specs()) {
    if (spec.key.find('<') == std::string::npos) keys.push_back(spec.key);
  }
  for (const auto& spec : s.metric_specs())
    keys.push_back(spec.key);
  if (r) {
    for (const auto& [k, v] : r->metrics)
      keys.push_back(k);
    for (const auto& [k, why] : r->undefined)
      keys.push_back(k);
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

std::string metrics_to_json(const Metrics& m, const UndefinedMetrics& undefined, int indent) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [k, v] : m) {
    if (std::isfinite(v)) j[k] = v;
  }
  nlohmann::ordered_json u = nlohmann::ordered_json::object();
  for (const auto& [k, why] : undefined)
    u[k] = why;
  for (const auto& [k, v] : m) {
    if (!std::isfinite(v) && !undefined.count(k)) u[k] = "no finite value";
  }
  if (!u.empty()) j["undefined"] = u;
  return j.dump(indent);
}

std::vector<std::string> ScenarioRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, f] : preset_factories_)
    out.push_back(name);
  return out;
}

void ScenarioRegistry::add_from_preset(std::string name, PresetFactory factory) {
  preset_factories_[std::move(name)] = std::move(factory);
}

const ScenarioRegistry::PresetFactory* ScenarioRegistry::from_preset(
    const std::string& name) const {
  auto it = preset_factories_.find(name);
  return it == preset_factories_.end() ? nullptr : &it->second;
}

const ScenarioRegistry& scenarios() {
  static const ScenarioRegistry registry = [] {
    ScenarioRegistry r;
    register_all_scenarios(r);
    return r;
  }();
  return registry;
}

std::string unknown_scenario(const std::string& name) {
  return unknown_message("scenario", name, scenarios().names()) +
         ": a preset names \"scenario\": \"model\" and declares its \"model\" block";
}

}  // namespace kfw
