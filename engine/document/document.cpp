#include "document/document.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string_view>
#include <utility>

#include "core/retired.h"
#include "core/suggest.h"
#include "document/workspace.h"

namespace kfw {

namespace {

// The one notice of a session that named a retired built-in.
std::string retired_notice(const std::string& where, std::string_view scenario,
                           const std::string& preset, const std::set<std::string>& dropped) {
  std::string n = where + ": scenario '" + std::string(scenario) + "' is retired: loaded as " +
                  "the model file " + retired_model_path(scenario);
  std::error_code ec;
  if (!std::filesystem::equivalent(preset, retired_model_path(scenario), ec)) {
    n += " (through the preset " + preset + ")";
  }
  n += " with the session's values";
  if (!dropped.empty()) {
    n += " (dropped, not in the model file:";
    for (const auto& k : dropped)
      n += " " + truncate_token(k);
    n += ")";
  }
  return n + "; kfw-cli upgrade " + where + " rewrites it in the current form";
}

// Drops the parts of a view state (a JSON object; the older ':'-separated form holds none) that
// belonged to a scenario's own view: its plots' zoom and the plots chosen for presentation
// (widgets/main_window.cpp, registerViewState). Returns the parts dropped, "" for none.
std::string drop_view_parts(std::string& blob) {
  if (blob.empty() || blob.front() != '{') return {};
  nlohmann::json j = nlohmann::json::parse(blob, nullptr, false);
  if (!j.is_object()) return {};
  std::string parts;
  if (j.erase("zoom")) parts = "zoom";
  if (auto p = j.find("presentation"); p != j.end() && p->is_object() && p->erase("plots")) {
    parts += std::string(parts.empty() ? "" : ", ") + "presentation.plots";
  }
  if (!parts.empty()) blob = j.dump();
  return parts;
}

}  // namespace

Expected<Document> Document::open(const std::string& preset, const std::optional<std::string>& data,
                                  const std::vector<std::string>& assignments,
                                  const ImportArgs& import) {
  auto ws = open_workspace(preset, data, assignments);
  if (!ws) return ws.err();
  if (auto st = apply_import_args(import, *ws); !st) return st.err();
  Document d = from_preset(ws->preset);
  d.state_.values = ws->values;
  if (ws->data_path) d.state_.data = DataRef{*ws->data_path, ws->mapping};
  d.saved_ = d.state_;
  return d;
}

Document Document::from_preset(Preset preset) {
  Document d;
  d.notices_ = preset.notices;
  d.preset_ = std::move(preset);
  d.state_.values = d.preset_.values;
  if (d.preset_.data_path) d.state_.data = DataRef{*d.preset_.data_path, d.preset_.mapping};
  d.saved_ = d.state_;
  return d;
}

void Document::push(std::string label, std::string merge_key) {
  undo_.push_back({std::move(label), state_, std::move(merge_key)});
  redo_.clear();
}

Status Document::set_value(const std::string& key, double value, UndoMerge merge) {
  if (auto st = scenario().params().check(key, value); !st) return st;
  auto it = state_.values.find(key);
  if (it != state_.values.end() && it->second == value) return Ok{};
  const bool join = merge == UndoMerge::kMergeSameKey && !undo_.empty() &&
                    undo_.back().merge_key == key && redo_.empty();
  if (!join) push("set " + key, merge == UndoMerge::kMergeSameKey ? key : std::string());
  state_.values[key] = value;
  return Ok{};
}

Status Document::set_values(const ParamValues& values, const std::string& label) {
  ParamValues next = state_.values;
  for (const auto& [k, v] : values) {
    if (auto st = scenario().params().check(k, v); !st) return st;
    next[k] = v;
  }
  if (next == state_.values) return Ok{};
  push(label);
  state_.values = std::move(next);
  return Ok{};
}

Status Document::apply_assignment(const std::string& assignment) {
  ParamValues next = state_.values;
  if (auto st = scenario().params().apply_assignment(assignment, next); !st) return st;
  return set_values(next, "set " + assignment);
}

void Document::set_data(std::optional<DataRef> data) {
  if (data == state_.data) return;
  push(data ? "open " + data->path : "use simulated data");
  state_.data = std::move(data);
}

Status Document::set_mapping(const Mapping& mapping) {
  if (!state_.data) return Error{"mapping: no dataset is loaded (the data are simulated)"};
  if (state_.data->mapping == mapping) return Ok{};
  push("change mapping");
  state_.data->mapping = mapping;
  return Ok{};
}

void Document::set_tuning_set(std::vector<DataRef> logs) {
  if (logs == state_.tuning_set) return;
  push("change tuning set");
  state_.tuning_set = std::move(logs);
}

void Document::add_snapshot(Snapshot s) {
  push("pin " + s.name);
  state_.snapshots.push_back(std::move(s));
}

Status Document::remove_snapshot(std::size_t index) {
  if (index >= state_.snapshots.size()) {
    return Error{"snapshot " + std::to_string(index + 1) + ": no such snapshot"};
  }
  push("delete snapshot " + state_.snapshots[index].name);
  state_.snapshots.erase(state_.snapshots.begin() + static_cast<std::ptrdiff_t>(index));
  return Ok{};
}

void Document::clear_snapshots() {
  if (state_.snapshots.empty()) return;
  push("clear snapshots");
  state_.snapshots.clear();
}

void Document::reset_to_preset() {
  if (state_.values == preset_.values) return;
  push("reset to preset");
  state_.values = preset_.values;
}

bool Document::undo() {
  if (undo_.empty()) return false;
  Step s = std::move(undo_.back());
  undo_.pop_back();
  redo_.push_back({s.label, state_, {}});
  state_ = std::move(s.before);
  return true;
}

bool Document::redo() {
  if (redo_.empty()) return false;
  Step s = std::move(redo_.back());
  redo_.pop_back();
  undo_.push_back({s.label, state_, {}});
  state_ = std::move(s.before);
  return true;
}

Session Document::to_session() const {
  Session s;
  s.preset_path = preset_.path;
  s.scenario = preset_.scenario;
  s.values = state_.values;
  if (state_.data) {
    s.data_path = state_.data->path;
    s.mapping = state_.data->mapping;
    if (auto h = file_hash(state_.data->path)) s.data_hash = *h;
  }
  s.tuning_set = state_.tuning_set;
  s.snapshots = state_.snapshots;
  s.window_state = view_state_;
  return s;
}

Expected<Document> Document::from_session(const Session& s, const std::string& where) {
  auto p = load_preset(resolve_preset_path(s.preset_path));
  if (!p) return Error{where + ": preset: " + p.error()};
  const RetiredScenario* retired = find_retired(s.scenario);
  if (p->scenario != s.scenario && !(retired && p->scenario == "model")) {
    return Error{where + ": scenario: '" + s.scenario + "' but the preset runs '" + p->scenario +
                 "'"};
  }
  std::set<std::string> dropped(p->dropped_keys.begin(), p->dropped_keys.end());
  Document d = from_preset(std::move(*p));
  if (retired) d.notices_.clear();  // the session's notice below says it once
  const ParamTable& table = d.scenario().params();
  // A retired built-in's keys its model file lacks (`window`) are dropped, not refused.
  auto kept = [&](const std::string& k) {
    if (!retired || table.find(k)) return true;
    dropped.insert(k);
    return false;
  };
  for (const auto& [k, v] : s.values) {
    if (!kept(k)) continue;
    if (auto st = table.check(k, v); !st) return Error{where + ": values." + k + ": " + st.error()};
    d.state_.values[k] = v;
  }
  std::vector<Snapshot> snapshots;
  for (const auto& snap : s.snapshots) {
    Snapshot kept_snap{snap.name, {}};
    for (const auto& [k, v] : snap.values) {
      if (!kept(k)) continue;
      if (auto st = table.check(k, v); !st) {
        return Error{where + ": snapshots." + snap.name + "." + k + ": " + st.error()};
      }
      kept_snap.values[k] = v;
    }
    snapshots.push_back(std::move(kept_snap));
  }
  d.state_.data.reset();
  if (s.data_path) d.state_.data = DataRef{*s.data_path, s.mapping};
  d.state_.tuning_set = s.tuning_set;
  d.state_.snapshots = std::move(snapshots);
  d.view_state_ = s.window_state;
  std::vector<std::string> notices = s.notices;
  if (retired) {
    notices.push_back(retired_notice(where, retired->scenario, d.preset_.path, dropped));
    if (auto parts = drop_view_parts(d.view_state_); !parts.empty()) {
      notices.push_back(where + ": view state of the retired '" + std::string(retired->scenario) +
                        "' view dropped (" + parts + ")");
    }
  }
  d.notices_.insert(d.notices_.end(), notices.begin(), notices.end());
  d.saved_ = d.state_;  // a session just opened loses nothing
  return d;
}

}  // namespace kfw
