#include "model/model_spec.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>

#include "core/limits.h"
#include "core/suggest.h"
#include "model/imm/imm_spec.h"
#include "model/loop/loop_spec.h"
#include "model/model_derived.h"
#include "model/model_expressions.h"
#include "model/model_noise.h"
#include "model/model_reader.h"
#include "model/world/model_world.h"

namespace kfw::model {

using nlohmann::json;

namespace {

using detail::idx;
using detail::kInputSim;
using detail::kInputSimWhat;
using detail::kLinear;
using detail::kLinearWhat;
using detail::kParamsOnly;
using detail::kParamsOnlyWhat;
using detail::parse_process;
using detail::Reader;

// A new symbol name must be an identifier, not reserved, not yet taken.
Status check_name(const Reader& p, const Symbols& symbols, const std::string& name,
                  const std::string& key) {
  if (name.size() > limits::kMaxNameChars) {
    return p.error(key, "a name of " + std::to_string(name.size()) + " characters (at most " +
                            std::to_string(limits::kMaxNameChars) + ", docs/limits.md)");
  }
  if (!is_identifier(name)) {
    return p.error(key,
                   quote_token(name) + " is not a name (letters, digits and _, not first a digit)");
  }
  if (is_reserved_name(name)) return p.error(key, quote_token(name) + " is reserved");
  if (symbols.find(name) >= 0) return p.error(key, quote_token(name) + " is already a symbol");
  return Ok{};
}

// A world's symbols for the simulator's parameters: the declared sim.X as X. Where the filter has
// a parameter X too (seed 004's sigma_range and sim.sigma_range), the world's X is sim.X: the
// simulator's value shadows the filter's, which the world never reads.
Status add_sim_symbols(const Reader& p, const ParamTable& params, ModelSpec& m) {
  for (const auto& spec : params.specs()) {
    if (spec.key.rfind("sim.", 0) != 0) continue;
    const std::string name = spec.key.substr(4);
    if (!is_identifier(name) || is_reserved_name(name)) continue;
    if (const int slot = m.symbols.find(name); slot >= 0) {
      const auto it = std::find(m.param_slots.begin(), m.param_slots.end(), slot);
      if (it == m.param_slots.end()) {
        return p.error("model.world", "the parameter '" + spec.key +
                                          "' would be the world's symbol '" + name +
                                          "', which the world already declares");
      }
      m.param_keys[static_cast<std::size_t>(it - m.param_slots.begin())] = spec.key;
      continue;
    }
    m.param_slots.push_back(m.symbols.add(name, kParamSymbol));
    m.param_keys.push_back(spec.key);
  }
  return Ok{};
}

// The report side of a filter model (derived quantities, named metrics, plot blocks; issue 30)
// reads each simulator parameter sim.X as X where no symbol of the model is named X: seed 003's
// tracking RMSE counts from sim.step_time. The model itself (x0, P0, process, channels) is
// parsed before and never reads the simulator's parameters.
void add_free_sim_symbols(const ParamTable& params, ModelSpec& m) {
  for (const auto& spec : params.specs()) {
    if (spec.key.rfind("sim.", 0) != 0) continue;
    const std::string name = spec.key.substr(4);
    if (!is_identifier(name) || is_reserved_name(name) || m.symbols.find(name) >= 0) continue;
    m.param_slots.push_back(m.symbols.add(name, kParamSymbol));
    m.param_keys.push_back(spec.key);
  }
}

// noise_param on an input or a channel (version 2), refused in a version-1 file.
Status check_noise_version(const Reader& p, const json& j) {
  if (auto it = j.find("inputs"); it != j.end() && it->is_array()) {
    for (std::size_t i = 0; i < it->size(); ++i) {
      if ((*it)[i].is_object() && (*it)[i].contains("noise_param")) {
        return p.error(idx("model.inputs", i) + ".noise_param",
                       "a version-2 key: set \"version\": 2");
      }
    }
  }
  if (auto it = j.find("measurements"); it != j.end() && it->is_object()) {
    for (auto c = it->begin(); c != it->end(); ++c) {
      if (c->is_object() && c->contains("noise_param")) {
        return p.error("model.measurements." + truncate_token(c.key()) + ".noise_param",
                       "a version-2 key: set \"version\": 2");
      }
    }
  }
  return Ok{};
}

// The keys that version 2 added, refused in a file that says version 1 (the writer writes the
// lowest version that holds the file, so a version-1 file never needs them).
Status check_version_keys(const Reader& p, const json& j, int version) {
  if (version >= 2) return Ok{};
  for (const char* k : {"expressions", "world", "derived", "sim", "plots", "groups", "modes",
                        "metrics", "metrics_from", "first_panels", "controller"}) {
    if (j.contains(k))
      return p.error(std::string("model.") + k, "a version-2 key: set \"version\": 2");
  }
  if (j.contains("process") && j["process"].is_object() && j["process"].contains("xdot")) {
    return p.error("model.process.xdot", "a version-2 key: set \"version\": 2");
  }
  return check_noise_version(p, j);
}

// Grid axes over a name the preset does not declare (model.modes.grid[i].param): a symbol of the
// expressions, set by the modes (and to the grid's centre outside them), with no slider.
Status add_mode_params(const Reader& p, const json& j, const ParamTable& params, ModelSpec& m) {
  const auto modes = j.find("modes");
  if (modes == j.end() || !modes->is_object() || !modes->contains("grid")) return Ok{};
  const json& grid = (*modes)["grid"];
  if (!grid.is_array()) return Ok{};  // parse_modes says what is wrong
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (!grid[i].is_object() || !grid[i].contains("param") || !grid[i]["param"].is_string())
      continue;
    const std::string name = grid[i]["param"].get<std::string>();
    if (params.find(name) || m.symbols.find(name) >= 0) continue;
    const std::string key = idx("model.modes.grid", i) + ".param";
    if (auto st = check_name(p, m.symbols, name, key); !st) return st;
    m.param_slots.push_back(m.symbols.add(name, kParamSymbol));
    m.param_keys.push_back(name);
    m.mode_params.push_back(name);
  }
  return Ok{};
}

// "sim": {"dt": "sim.Ts"}: the declared parameter that is the simulation's step.
Status parse_sim_keys(const Reader& p, const json& j, const ParamTable& params, ModelSpec& m) {
  auto it = j.find("sim");
  if (it == j.end()) return Ok{};
  if (!it->is_object()) return p.error("model.sim", "expected {\"dt\": \"PARAMETER\"}");
  if (auto st = p.only_keys(*it, "model.sim", {"dt"}); !st) return st;
  auto dt = p.string(*it, "dt", "model.sim", false, "sim.dt");
  if (!dt) return dt.err();
  if (!params.find(*dt)) {
    std::vector<std::string> names;
    for (const auto& spec : params.specs())
      names.push_back(spec.key);
    return p.error("model.sim.dt", unknown_message("parameter", *dt, names));
  }
  m.sim_dt_key = *dt;
  return Ok{};
}

// The states: names (symbols), units, labels, angles.
Status parse_states(const Reader& p, const json& j, ModelSpec& m) {
  if (!j.contains("states") || !j["states"].is_array() || j["states"].empty()) {
    return p.error("model.states", "expected a non-empty list of states");
  }
  if (j["states"].size() > limits::kMaxStates) {
    return p.error("model.states", std::to_string(j["states"].size()) + " states: more than the " +
                                       "limit of " + std::to_string(limits::kMaxStates) +
                                       " (docs/limits.md)");
  }
  for (std::size_t i = 0; i < j["states"].size(); ++i) {
    const json& s = j["states"][i];
    const std::string skey = idx("model.states", i);
    StateSpec st;
    if (s.is_string()) {
      st.name = s.get<std::string>();
    } else if (s.is_object()) {
      if (auto ok = p.only_keys(s, skey, {"name", "unit", "label", "angle"}); !ok) return ok.err();
      auto nm = p.string(s, "name", skey, true);
      if (!nm) return nm.err();
      st.name = *nm;
      auto unit = p.string(s, "unit", skey, false);
      if (!unit) return unit.err();
      st.unit = *unit;
      auto label = p.string(s, "label", skey, false, st.name);
      if (!label) return label.err();
      st.label = *label;
      auto a = p.angle(s, skey);
      if (!a) return a.err();
      st.angle = *a;
    } else {
      return p.error(skey, "expected a state name or {\"name\", \"unit\", \"label\", \"angle\"}");
    }
    if (st.label.empty()) st.label = st.name;
    if (auto ok = check_name(p, m.symbols, st.name, skey + ".name"); !ok) return ok.err();
    m.state_slots.push_back(m.symbols.add(st.name, kStateSymbol));
    m.states.push_back(st);
  }
  return Ok{};
}

// The inputs (symbols, columns of the same name) and their simulation expressions.
Status parse_inputs(const Reader& p, const json& j, ModelSpec& m,
                    std::set<std::string>& roles_seen) {
  if (auto it = j.find("inputs"); it != j.end()) {
    if (!it->is_array()) return p.error("model.inputs", "expected a list of inputs");
    for (std::size_t i = 0; i < it->size(); ++i) {
      const json& u = (*it)[i];
      const std::string ukey = idx("model.inputs", i);
      InputSpec in;
      in.sim = Expr{"0", Dep::kConst, 0.0};
      if (u.is_string()) {
        in.name = u.get<std::string>();
      } else if (u.is_object()) {
        if (auto ok = p.only_keys(u, ukey, {"name", "unit", "label", "sim", "noise_param", "age"});
            !ok) {
          return ok.err();
        }
        auto nm = p.string(u, "name", ukey, true);
        if (!nm) return nm.err();
        in.name = *nm;
        auto unit = p.string(u, "unit", ukey, false);
        if (!unit) return unit.err();
        in.unit = *unit;
        auto label = p.string(u, "label", ukey, false, in.name);
        if (!label) return label.err();
        in.label = *label;
      } else {
        return p.error(ukey, "expected an input name or {\"name\", \"unit\", \"label\", \"sim\"}");
      }
      if (auto ok = check_name(p, m.symbols, in.name, ukey + ".name"); !ok) return ok.err();
      roles_seen.insert(in.name);
      m.input_slots.push_back(m.symbols.add(in.name, kInputSymbol));
      auto age = p.string(u.is_object() ? u : json::object(), "age", ukey, false);
      if (!age) return age.err();
      in.age = *age;
      m.input_age_slots.push_back(-1);
      if (!in.age.empty()) {
        if (m.version < 2) return p.error(ukey + ".age", "a version-2 key: set \"version\": 2");
        if (auto ok = check_name(p, m.symbols, in.age, ukey + ".age"); !ok) return ok.err();
        m.input_age_slots.back() = m.symbols.add(in.age, kInputSymbol);
      }
      m.inputs.push_back(in);
    }
    // Simulation expressions once every symbol is known.
    for (std::size_t i = 0; i < it->size(); ++i) {
      const json& u = (*it)[i];
      if (u.is_object() && u.contains("sim")) {
        auto e = p.expr(u["sim"], idx("model.inputs", i) + ".sim", kInputSim, kInputSimWhat);
        if (!e) return e.err();
        m.inputs[i].sim = *e;
      }
    }
  }
  return Ok{};
}

// x0 (expressions of parameters or a column's first sample) and P0.
Status parse_initial(const Reader& p, const json& j, ModelSpec& m) {
  const std::string key = "model";
  const int n = m.n();
  if (!j.contains("x0")) return p.error(key, "missing key 'x0'");
  const json& x0 = j["x0"];
  if (!x0.is_array() || x0.size() != static_cast<std::size_t>(n)) {
    return p.error("model.x0", "wrong dimensions: expected a list of " + std::to_string(n) +
                                   " entries, one per state");
  }
  for (std::size_t i = 0; i < x0.size(); ++i) {
    const std::string xkey = idx("model.x0", i);
    InitialSpec init;
    if (x0[i].is_object()) {
      if (auto ok = p.only_keys(x0[i], xkey, {"first", "default"}); !ok) return ok.err();
      auto col = p.string(x0[i], "first", xkey, true);
      if (!col) return col.err();
      init.first_column = *col;
      auto e = p.expr(x0[i].value("default", json("0")), xkey + ".default", kParamsOnly,
                      kParamsOnlyWhat);
      if (!e) return e.err();
      init.value = *e;
    } else {
      auto e = p.expr(x0[i], xkey, kParamsOnly, kParamsOnlyWhat);
      if (!e) return e.err();
      init.value = *e;
    }
    m.x0.push_back(init);
  }
  if (!j.contains("P0")) return p.error(key, "missing key 'P0'");
  auto P0 = p.matrix(j["P0"], "model.P0", n, n, kParamsOnly, kParamsOnlyWhat, true);
  if (!P0) return P0.err();
  m.P0 = *P0;
  if (auto st = p.symmetric(m.P0); !st) return st.err();
  return Ok{};
}

std::vector<std::string> state_names(const ModelSpec& m) {
  std::vector<std::string> names;
  for (const auto& s : m.states)
    names.push_back(s.name);
  return names;
}

// "primary": a state, or (version 2) a non-empty list of distinct states (default: the first).
Status parse_primary(const Reader& p, const json& j, ModelSpec& m) {
  const std::string key = "model.primary";
  auto it = j.find("primary");
  if (it == j.end() || it->is_null()) {
    m.primary = {m.states.front().name};
    return Ok{};
  }
  const bool list = it->is_array() && !it->empty();
  if (!it->is_string() && !list) {
    return p.error(key, "expected a state or a non-empty list of states");
  }
  if (list && m.version < 2) {
    return p.error(key, "a list of states is a version-2 form: set \"version\": 2");
  }
  const json names = list ? *it : json::array({*it});
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string at = list ? idx(key, i) : key;
    if (!names[i].is_string()) return p.error(at, "expected a state name");
    const std::string name = names[i].get<std::string>();
    if (m.state_index(name) < 0) {
      return p.error(at,
                     quote_token(name) + " is not a state" + did_you_mean(name, state_names(m)));
    }
    if (std::find(m.primary.begin(), m.primary.end(), name) != m.primary.end()) {
      return p.error(at, quote_token(name) + " is named twice");
    }
    m.primary.push_back(name);
  }
  return Ok{};
}

// The truth columns, the primary state and the default filter.
Status parse_outputs(const Reader& p, const json& j, ModelSpec& m,
                     const std::set<std::string>& roles_seen) {
  const std::string key = "model";
  const int n = m.n();
  m.truth.assign(static_cast<std::size_t>(n), std::string());
  if (auto it = j.find("truth"); it != j.end()) {
    if (!it->is_object()) return p.error("model.truth", "expected {\"state\": \"column\", ...}");
    for (auto t = it->begin(); t != it->end(); ++t) {
      const int s = m.state_index(t.key());
      if (s < 0 && m.world_block && t->is_string() && !roles_seen.count(t->get<std::string>())) {
        // A world may write a sub-expression (a quantity not among its states) as truth.
        const int slot = m.symbols.find(t.key());
        if (slot >= 0 && m.symbols.kinds[static_cast<std::size_t>(slot)] == kSubSymbol) {
          auto e = p.expr(json(t.key()), "model.truth." + t.key(), kAllSymbols, "");
          if (!e) return e.err();
          m.truth_exprs.emplace_back(t->get<std::string>(), *e);
          continue;
        }
      }
      if (s < 0) {
        return p.error("model.truth." + truncate_token(t.key()),
                       "unknown state" + did_you_mean(t.key(), state_names(m)));
      }
      if (!t->is_string() || t->get<std::string>().empty() || t->get<std::string>() == "t") {
        return p.error("model.truth." + t.key(), "expected a column name");
      }
      if (roles_seen.count(t->get<std::string>())) {
        return p.error("model.truth." + t.key(), "column '" + t->get<std::string>() +
                                                     "' is already an input or a measurement");
      }
      m.truth[static_cast<std::size_t>(s)] = t->get<std::string>();
    }
  }
  if (auto st = parse_primary(p, j, m); !st) return st.err();
  const auto choices = filter_choices(m);
  auto filter = p.string(j, "filter", key, false, choices.front());
  if (!filter) return filter.err();
  if (std::find(choices.begin(), choices.end(), *filter) == choices.end()) {
    std::string list;
    for (const auto& c : choices)
      list += " " + c;
    return p.error("model.filter", "'" + *filter + "' is not a filter for this model (one of" +
                                       list + (m.linear() ? "" : "; kf needs F and H") + ")");
  }
  m.filter = *filter;
  return Ok{};
}

}  // namespace

Dep MatrixSpec::dep() const {
  Dep d = Dep::kConst;
  for (const auto& x : e)
    d = std::max(d, x.dep);
  return d;
}

bool ModelSpec::linear() const {
  if (nonlinear_process()) return false;
  return std::all_of(channels.begin(), channels.end(), [](const auto& c) { return c.linear; });
}

bool ModelSpec::linear_modes() const {
  if (!linear()) return false;
  if (!modes) return true;
  return std::all_of(modes->list.begin(), modes->list.end(),
                     [](const ModeSpec& m) { return !m.model || m.model->linear(); });
}

bool ModelSpec::time_invariant() const {
  if (!linear() || modes) return false;
  const auto lti = [](const MatrixSpec& m) { return m.dep() <= Dep::kDt; };
  if (process.form == ProcessForm::kLinear &&
      !(lti(process.F) && lti(process.B) && lti(process.Q))) {
    return false;
  }
  return std::all_of(channels.begin(), channels.end(),
                     [&](const auto& c) { return lti(c.H) && lti(c.R); });
}

int ModelSpec::state_index(const std::string& name) const {
  for (std::size_t i = 0; i < states.size(); ++i) {
    if (states[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<std::string> filter_choices(const ModelSpec& spec) {
  if (!spec.linear_modes()) return {"ekf", "ukf"};
  // The fixed DARE gain (issue 30): a linear time-invariant model with one channel.
  if (spec.time_invariant() && spec.channels.size() == 1 && !spec.modes && spec.groups.empty())
    return {"kf", "ekf", "ukf", "steady"};
  return {"kf", "ekf", "ukf"};
}

Expected<ModelSpec> parse_model(const json& j, const ParamTable& params, const std::string& path,
                                bool world) {
  ModelSpec m;
  m.path = path;
  Reader p(path, m.symbols);
  const std::string key = "model";
  if (!j.is_object()) return p.error(key, "expected an object");
  if (auto st = p.only_keys(
          j, key,
          {"version", "description", "states",       "inputs",       "expressions",  "x0",
           "P0",      "process",     "measurements", "truth",        "primary",      "filter",
           "world",   "derived",     "noise",        "clocks",       "sim",          "plots",
           "groups",  "modes",       "metrics",      "metrics_from", "first_panels", "controller",
           "limits",  "events"});
      !st) {
    return st.err();
  }
  if (!j.contains("version") || !j["version"].is_number_integer()) {
    return p.error("model.version", "missing or not an integer");
  }
  m.version = j["version"].get<int>();
  if (m.version < 1 || m.version > kModelVersion) {
    return p.error("model.version", "is " + j["version"].dump() +
                                        ", this build reads versions 1 to " +
                                        std::to_string(kModelVersion));
  }
  if (auto st = check_version_keys(p, j, m.version); !st) return st.err();
  if (auto st = parse_sim_keys(p, j, params, m); !st) return st.err();

  // Symbols: the parameters whose keys are names, dt, t, the states, the inputs.
  for (const auto& spec : params.specs()) {
    if (is_identifier(spec.key) && !is_reserved_name(spec.key)) {
      m.param_slots.push_back(m.symbols.add(spec.key, kParamSymbol));
      m.param_keys.push_back(spec.key);
    }
  }
  if (world) {
    if (auto st = add_sim_symbols(p, params, m); !st) return st.err();
  } else if (auto st = add_mode_params(p, j, params, m); !st) {
    return st.err();
  }
  m.dt_slot = m.symbols.add("dt", kDtSymbol);
  m.t_slot = m.symbols.add("t", kTimeSymbol);
  m.world_block = world;
  for (const char* k : {"noise", "clocks", "limits", "events"}) {
    if (j.contains(k) && !world) {
      return p.error(std::string("model.") + k,
                     std::string("a key of the world block: declare it as model.world.") + k);
    }
  }
  if (world) {
    if (auto st = detail::parse_noise_sources(p, j, m); !st) return st.err();
    if (auto st = detail::parse_clocks(p, j, m); !st) return st.err();
  }

  if (auto st = parse_states(p, j, m); !st) return st.err();

  std::set<std::string> roles_seen;
  if (auto st = parse_inputs(p, j, m, roles_seen); !st) return st.err();

  if (auto st = detail::add_column_symbols(p, j, m); !st) return st.err();
  if (auto it = j.find("expressions"); it != j.end()) {
    if (auto st = parse_expressions(*it, path, m.symbols); !st) return st.err();
  }

  if (auto st = parse_initial(p, j, m); !st) return st.err();

  if (!j.contains("process")) return p.error(key, "missing key 'process'");
  if (auto st = parse_process(p, j["process"], m); !st) return st.err();

  if (!j.contains("measurements") || !j["measurements"].is_object() || j["measurements"].empty()) {
    return p.error("model.measurements", "expected an object of one or more channels");
  }
  if (j["measurements"].size() > limits::kMaxChannels) {
    return p.error("model.measurements",
                   std::to_string(j["measurements"].size()) + " channels: more than the limit of " +
                       std::to_string(limits::kMaxChannels) + " (docs/limits.md)");
  }
  for (auto it = j["measurements"].begin(); it != j["measurements"].end(); ++it) {
    if (!is_identifier(it.key())) {
      return p.error("model.measurements." + it.key(),
                     "a channel name is a name (letters, digits and _)");
    }
    auto c = detail::parse_channel(p, it.key(), it.value(), m, params, roles_seen);
    if (!c) return c.err();
    const std::string ckey = "model.measurements." + it.key();
    if (world) {
      if (auto st = detail::parse_sensor(p, it.value(), ckey, params, m, *c); !st) return st.err();
    } else if (auto st = detail::parse_missing(p, it.value(), ckey, *c); !st) {
      return st.err();
    }
    m.channels.push_back(std::move(*c));
  }
  if (auto st = detail::resolve_initial_channels(p, m); !st) return st.err();
  if (world) {
    if (auto st = detail::parse_limits(p, j, m); !st) return st.err();
    if (auto st = detail::parse_events(p, j, m); !st) return st.err();
  }

  if (auto it = j.find("groups"); it != j.end()) {
    if (world) return p.error("model.groups", "a world's sensors are not grouped: group channels");
    if (auto st = detail::parse_groups(p, *it, params, m); !st) return st.err();
  }
  if (auto st = parse_noise_params(j, m, params, world); !st) return st.err();
  if (auto st = parse_outputs(p, j, m, roles_seen); !st) return st.err();
  if (auto it = j.find("world"); it != j.end()) {
    if (world) return p.error("model.world", "a world holds no world of its own");
    auto w = parse_world(j, params, path, m);
    if (!w) return w.err();
    m.world = std::move(*w);
  }
  if (j.contains("controller")) {
    if (world)
      return p.error("model.controller", "a world has no controller: declare it in the model");
    if (j.contains("modes")) {
      return p.error("model.controller", "a controller with modes (an IMM) is not supported yet");
    }
    auto c = parse_controller(j, params, m);
    if (!c) return c.err();
    m.controller = std::move(*c);
  }
  if (!world) add_free_sim_symbols(params, m);
  if (auto it = j.find("derived"); it != j.end()) {
    detail::add_grid_symbols(j, m);
    if (auto st = parse_derived(p, *it, m); !st) return st.err();
  }
  if (auto it = j.find("plots"); it != j.end()) {
    if (world) return p.error("model.plots", "a world draws no plots: declare them in the model");
    if (auto st = parse_plots(p, *it, params, m); !st) return st.err();
  }
  if (j.contains("modes")) {
    if (world) return p.error("model.modes", "a world has no modes: declare them in the model");
    auto modes = detail::parse_modes(p, j, params, m);
    if (!modes) return modes.err();
    m.modes = std::move(*modes);
    // A mode's f or h rules out the kf the base model alone allowed.
    const auto choices = filter_choices(m);
    if (std::find(choices.begin(), choices.end(), m.filter) == choices.end()) {
      if (j.contains("filter")) {
        return p.error("model.filter", "'" + m.filter +
                                           "' is not a filter for this model (one of ekf ukf; "
                                           "a mode's process or h is not linear)");
      }
      m.filter = choices.front();
    }
  }
  if (auto it = j.find("metrics"); it != j.end()) {
    if (world)
      return p.error("model.metrics", "a world reports no metrics: declare them in the model");
    if (auto st = parse_stat_metrics(p, *it, m); !st) return st.err();
  }
  if (auto it = j.find("metrics_from"); it != j.end()) {
    if (world) return p.error("model.metrics_from", "a world reports no metrics");
    auto e = p.expr(*it, "model.metrics_from", kParamsOnly, kParamsOnlyWhat);
    if (!e) return e.err();
    m.metrics_from = *e;
  }
  if (auto it = j.find("first_panels"); it != j.end()) {
    if (world) return p.error("model.first_panels", "a world draws no panels");
    if (auto st = parse_first_panels(p, *it, m); !st) return st.err();
  }
  return m;
}

}  // namespace kfw::model
