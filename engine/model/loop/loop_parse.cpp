// The keys of closed loops (version 2, issue 30): model.controller, a world's limits and events,
// a world sensor's impulses and a filter channel's missing flag. Documented in
// presets/models/README.md, "Closed loops".
#include <algorithm>
#include <nlohmann/json.hpp>

#include "model/loop/loop_spec.h"
#include "model/model_expressions.h"
#include "model/model_reader.h"

namespace kfw::model {

namespace detail {

namespace {

Expected<Expr> param_expr(const Reader& p, const json& obj, const char* name,
                          const std::string& key, const char* def) {
  auto it = obj.find(name);
  return p.expr(it == obj.end() ? json(def) : *it, key + "." + name, kParamsOnly, kParamsOnlyWhat);
}

std::vector<std::string> state_names(const ModelSpec& m) {
  std::vector<std::string> out;
  for (const auto& s : m.states)
    out.push_back(s.name);
  return out;
}

}  // namespace

Status parse_limits(const Reader& p, const json& world, ModelSpec& m) {
  auto it = world.find("limits");
  if (it == world.end()) return Ok{};
  if (!it->is_object()) return p.error("model.limits", "expected {\"STATE\": {\"min\", \"max\"}}");
  for (auto l = it->begin(); l != it->end(); ++l) {
    const std::string key = "model.limits." + truncate_token(l.key());
    StateLimitSpec s;
    s.state = m.state_index(l.key());
    if (s.state < 0) return p.error(key, unknown_message("state", l.key(), state_names(m)));
    if (!l->is_object()) return p.error(key, "expected {\"min\", \"max\", \"rate\"}");
    if (auto st = p.only_keys(*l, key, {"min", "max", "rate"}); !st) return st;
    if (!l->contains("min") && !l->contains("max")) return p.error(key, "declare min, max or both");
    auto lo = param_expr(p, *l, "min", key, "-1e308");
    if (!lo) return lo.err();
    auto hi = param_expr(p, *l, "max", key, "1e308");
    if (!hi) return hi.err();
    s.lo = *lo;
    s.hi = *hi;
    if (auto r = l->find("rate"); r != l->end()) {
      if (!r->is_string()) return p.error(key + ".rate", "expected a state's name");
      s.rate = m.state_index(r->get<std::string>());
      if (s.rate < 0 || s.rate == s.state) {
        return p.error(key + ".rate",
                       unknown_message("state", r->get<std::string>(), state_names(m)) +
                           " (another state: the rate set to 0 at the limit)");
      }
    }
    m.limits.push_back(std::move(s));
  }
  return Ok{};
}

Status parse_events(const Reader& p, const json& world, ModelSpec& m) {
  auto it = world.find("events");
  if (it == world.end()) return Ok{};
  if (!it->is_object()) return p.error("model.events", "expected {\"NAME\": {\"when\": EXPR}}");
  for (auto e = it->begin(); e != it->end(); ++e) {
    const std::string key = "model.events." + truncate_token(e.key());
    if (!is_identifier(e.key())) return p.error(key, "an event's name is a name");
    EventSpec s;
    s.name = e.key();
    s.label = e.key();
    const json* when = &*e;
    if (e->is_object()) {
      if (auto st = p.only_keys(*e, key, {"when", "label", "ends"}); !st) return st;
      if (!e->contains("when")) return p.error(key, "missing key 'when'");
      if (auto flag = e->find("ends"); flag != e->end()) {
        if (!flag->is_boolean()) return p.error(key + ".ends", "expected true or false");
        s.ends = flag->get<bool>();
      }
      auto label = p.string(*e, "label", key, false, s.name);
      if (!label) return label.err();
      s.label = *label;
      when = &e->at("when");
    }
    auto x = p.expr(*when, e->is_object() ? key + ".when" : key, kAllSymbols,
                    "states, inputs, parameters, t and sub-expressions");
    if (!x) return x.err();
    s.when = *x;
    m.events.push_back(std::move(s));
  }
  return Ok{};
}

Status parse_impulses(const Reader& p, const json& j, const std::string& sensor_key,
                      ChannelSpec& c) {
  auto it = j.find("impulses");
  if (it == j.end()) return Ok{};
  const std::string key = sensor_key + ".impulses";
  if (j.contains("dropout")) {
    return p.error(key,
                   "a sensor has dropouts or impulses, not both (each draws from "
                   "dropout." +
                       c.name + ")");
  }
  if (!it->is_object()) return p.error(key, "expected {\"rate\", \"burst\", \"min\", \"max\"}");
  if (auto st = p.only_keys(*it, key, {"rate", "burst", "min", "max", "flag"}); !st) return st;
  for (const char* k : {"rate", "min", "max"}) {
    if (!it->contains(k)) return p.error(key, std::string("missing key '") + k + "'");
  }
  SensorSpec& s = c.sensor;
  s.impulses = true;
  for (auto [field, k, def] :
       {std::tuple{&s.impulse_rate, "rate", "0"}, std::tuple{&s.impulse_burst, "burst", "1"},
        std::tuple{&s.impulse_lo, "min", "0"}, std::tuple{&s.impulse_hi, "max", "0"}}) {
    auto e = param_expr(p, *it, k, key, def);
    if (!e) return e.err();
    *field = *e;
  }
  auto flag = p.string(*it, "flag", key, false);
  if (!flag) return flag.err();
  if (!flag->empty() && !is_identifier(*flag)) return p.error(key + ".flag", "a column's name");
  s.impulse_flag = *flag;
  return Ok{};
}

Status parse_missing(const Reader& p, const json& j, const std::string& channel_key,
                     ChannelSpec& c) {
  auto it = j.find("missing");
  if (it == j.end()) return Ok{};
  const std::string key = channel_key + ".missing";
  if (!it->is_object()) return p.error(key, "expected {\"column\", \"equals\", \"when\"}");
  if (auto st = p.only_keys(*it, key, {"column", "equals", "when"}); !st) return st;
  auto column = p.string(*it, "column", key, true);
  if (!column) return column.err();
  if (column->empty()) return p.error(key + ".column", "a column's name");
  c.missing.column = *column;
  auto equals = param_expr(p, *it, "equals", key, "0");
  if (!equals) return equals.err();
  auto when = param_expr(p, *it, "when", key, "1");
  if (!when) return when.err();
  c.missing.equals = *equals;
  c.missing.when = *when;
  return Ok{};
}

}  // namespace detail

namespace {

using detail::json;
using detail::Reader;

constexpr const char* kKey = "model.controller";

// Adds a symbol, refusing a name already taken (`what` says what the name is declared as).
Expected<int> add_name(const Reader& p, Symbols& s, const std::string& name, SymbolKind kind,
                       const std::string& key) {
  if (!is_identifier(name)) return p.error(key, quote_token(name) + " is not a name");
  if (is_reserved_name(name)) return p.error(key, quote_token(name) + " is reserved");
  if (s.find(name) >= 0) return p.error(key, quote_token(name) + " is already a symbol");
  return s.add(name, kind);
}

// Parameters (and sim.X as X where X is free), dt, t, the estimates and variances, the world's
// columns that are not outputs.
Status base_symbols(const Reader& p, const json& c, const ParamTable& params, const ModelSpec& m,
                    ControllerSpec& out) {
  Symbols& s = out.symbols;
  for (const auto& spec : params.specs()) {
    if (!is_identifier(spec.key) || is_reserved_name(spec.key)) continue;
    out.param_slots.push_back(s.add(spec.key, kParamSymbol));
    out.param_keys.push_back(spec.key);
  }
  for (const auto& spec : params.specs()) {
    if (spec.key.rfind("sim.", 0) != 0) continue;
    const std::string name = spec.key.substr(4);
    if (!is_identifier(name) || is_reserved_name(name) || s.find(name) >= 0) continue;
    out.param_slots.push_back(s.add(name, kParamSymbol));
    out.param_keys.push_back(spec.key);
  }
  out.dt_slot = s.add("dt", kDtSymbol);
  out.t_slot = s.add("t", kTimeSymbol);
  for (const auto& st : m.states) {
    auto e = add_name(p, s, st.name, kStateSymbol, std::string(kKey) + " (the filter's state)");
    if (!e) return e.err();
    out.estimate_slots.push_back(*e);
  }
  for (const auto& st : m.states) {
    auto e = add_name(p, s, "var_" + st.name, kStateSymbol,
                      std::string(kKey) + " (the variance of the filter's state)");
    if (!e) return e.err();
    out.variance_slots.push_back(*e);
  }
  std::vector<std::string> outputs;
  if (auto it = c.find("outputs"); it != c.end() && it->is_object()) {
    for (auto o = it->begin(); o != it->end(); ++o)
      outputs.push_back(o.key());
  }
  const ModelSpec& w = *m.world;
  std::vector<std::string> columns;
  for (const auto& ch : w.channels) {
    for (const auto& r : ch.roles)
      columns.push_back(r.name);
  }
  for (const auto& in : w.inputs) {
    if (std::find(outputs.begin(), outputs.end(), in.name) == outputs.end())
      columns.push_back(in.name);
  }
  for (const auto& col : columns) {
    if (!is_identifier(col) || is_reserved_name(col) || s.find(col) >= 0) continue;
    out.columns.push_back({col, s.add(col, kInputSymbol)});
  }
  return Ok{};
}

Status parse_reference(const Reader& p, const json& c, ControllerSpec& out) {
  auto it = c.find("reference");
  if (it == c.end()) return Ok{};
  const std::string key = std::string(kKey) + ".reference";
  if (!it->is_object() || !it->contains("name") || !it->contains("expression")) {
    return p.error(key, "expected {\"name\": COLUMN, \"expression\": EXPR of parameters and t}");
  }
  if (auto st = p.only_keys(*it, key, {"name", "expression", "unit"}); !st) return st;
  auto name = p.string(*it, "name", key, true);
  if (!name) return name.err();
  auto slot = add_name(p, out.symbols, *name, kInputSymbol, key + ".name");
  if (!slot) return slot.err();
  out.reference_name = *name;
  out.reference_slot = *slot;
  auto e = p.expr(it->at("expression"), key + ".expression", kParamSymbol | kTimeSymbol,
                  "parameters and t");
  if (!e) return e.err();
  out.reference = *e;
  return Ok{};
}

Status parse_outputs(const Reader& p, const json& c, const ModelSpec& m, ControllerSpec& out) {
  auto it = c.find("outputs");
  const std::string key = std::string(kKey) + ".outputs";
  if (it == c.end() || !it->is_object() || it->empty()) {
    return p.error(key,
                   "expected {\"INPUT\": {\"expression\", \"min\", \"max\"}}: one or more "
                   "of the world's inputs");
  }
  const ModelSpec& w = *m.world;
  std::vector<std::string> inputs;
  for (const auto& in : w.inputs)
    inputs.push_back(in.name);
  for (auto o = it->begin(); o != it->end(); ++o) {
    const std::string okey = key + "." + truncate_token(o.key());
    ControllerSpec::Output out_spec;
    out_spec.name = o.key();
    const auto at = std::find(inputs.begin(), inputs.end(), o.key());
    if (at == inputs.end()) {
      return p.error(okey, unknown_message("input of the world", o.key(), inputs) +
                               ": an output drives the world's input of its name");
    }
    out_spec.world_input = static_cast<int>(at - inputs.begin());
    // `unit` declares what the output is in: it must be the world input's (when that has one).
    if (o->is_object() && o->contains("unit")) {
      auto unit = p.string(*o, "unit", okey, false);
      if (!unit) return unit.err();
      const std::string& in_unit = w.inputs[static_cast<std::size_t>(out_spec.world_input)].unit;
      if (!in_unit.empty() && *unit != in_unit) {
        return p.error(okey + ".unit", quote_token(*unit) + ", but the world's input '" + o.key() +
                                           "' is in " + quote_token(in_unit));
      }
    }
    auto slot = add_name(p, out.symbols, o.key(), kTruthSymbol, okey);
    if (!slot) return slot.err();
    out_spec.slot = *slot;
    out.outputs.push_back(std::move(out_spec));
  }
  return Ok{};
}

Status parse_states(const Reader& p, const json& c, ControllerSpec& out) {
  auto it = c.find("states");
  if (it == c.end()) return Ok{};
  const std::string key = std::string(kKey) + ".states";
  if (!it->is_object()) return p.error(key, "expected {\"NAME\": {\"x0\", \"next\"}}");
  for (auto s = it->begin(); s != it->end(); ++s) {
    const std::string skey = key + "." + truncate_token(s.key());
    if (!s->is_object() || !s->contains("next")) {
      return p.error(skey, "expected {\"x0\": EXPR, \"next\": EXPR}");
    }
    if (auto st = p.only_keys(*s, skey, {"x0", "next"}); !st) return st;
    auto slot = add_name(p, out.symbols, s.key(), kStateSymbol, skey);
    if (!slot) return slot.err();
    out.states.push_back({s.key(), *slot, {}, {}});
  }
  return Ok{};
}

// The expressions, once every symbol is declared.
Status compile_all(const Reader& p, const json& c, ControllerSpec& out) {
  const std::string key = kKey;
  const char* every =
      "parameters, t, dt, the estimates, the world's columns, the reference, the "
      "controller's states and sub-expressions";
  for (auto& o : out.outputs) {
    const json& j = c["outputs"][o.name];
    const std::string okey = key + ".outputs." + o.name;
    const json* text = &j;
    if (j.is_object()) {
      if (auto st = p.only_keys(j, okey, {"expression", "min", "max", "unit"}); !st) return st;
      if (!j.contains("expression")) return p.error(okey, "missing key 'expression'");
      text = &j.at("expression");
      auto lo =
          p.expr(j.value("min", json("-1e308")), okey + ".min", kParamSymbol, "parameters only");
      if (!lo) return lo.err();
      auto hi =
          p.expr(j.value("max", json("1e308")), okey + ".max", kParamSymbol, "parameters only");
      if (!hi) return hi.err();
      o.lo = *lo;
      o.hi = *hi;
    } else {
      o.lo = Expr{"-1e308", Dep::kConst, -1e308};
      o.hi = Expr{"1e308", Dep::kConst, 1e308};
    }
    auto e = p.expr(*text, j.is_object() ? okey + ".expression" : okey, kAllSymbols, every);
    if (!e) return e.err();
    o.e = *e;
  }
  for (auto& s : out.states) {
    const json& j = c["states"][s.name];
    const std::string skey = key + ".states." + s.name;
    auto x0 = p.expr(j.value("x0", json("0")), skey + ".x0", kParamSymbol, "parameters only");
    if (!x0) return x0.err();
    s.x0 = *x0;
    auto next = p.expr(j["next"], skey + ".next", kAllSymbols | kTruthSymbol,
                       "every symbol of the controller, its outputs included");
    if (!next) return next.err();
    s.next = *next;
  }
  return Ok{};
}

Status parse_loop(const Reader& p, const json& c, const ParamTable& params, ControllerSpec& out) {
  auto it = c.find("loop");
  if (it == c.end()) return Ok{};
  const std::string key = std::string(kKey) + ".loop";
  if (!it->is_object()) return p.error(key, "expected {\"param\": CHOICE, LABEL: true/false}");
  auto alt = detail::choice_alternatives(p, *it, key, params, "true or false");
  if (!alt) return alt.err();
  out.loop_param = alt->param;
  for (const json* v : alt->values) {
    if (!v->is_boolean()) return p.error(key, "each label's value is true (closed) or false");
    out.closed_by_choice.push_back(v->get<bool>());
  }
  return Ok{};
}

Status parse_noise_free(const Reader& p, const json& c, ModelSpec& m, ControllerSpec& out) {
  auto it = c.find("noise_free");
  if (it == c.end()) return Ok{};
  const std::string key = std::string(kKey) + ".noise_free";
  if (!it->is_object()) return p.error(key, "expected {\"COLUMN\": \"WORLD_COLUMN\"}");
  std::vector<std::string> truth;
  for (const auto& col : m.world->truth) {
    if (!col.empty()) truth.push_back(col);
  }
  for (auto n = it->begin(); n != it->end(); ++n) {
    const std::string nkey = key + "." + truncate_token(n.key());
    if (!n->is_string() ||
        std::find(truth.begin(), truth.end(), n->get<std::string>()) == truth.end()) {
      return p.error(nkey,
                     unknown_message("truth column of the world",
                                     n->is_string() ? n->get<std::string>() : n->dump(), truth));
    }
    out.noise_free.emplace_back(n.key(), n->get<std::string>());
  }
  return Ok{};
}

// The loop's columns as symbols of the filter's derived series.
Status add_loop_columns(const Reader& p, const ControllerSpec& c, ModelSpec& m) {
  std::vector<std::string> names;
  if (!c.reference_name.empty()) names.push_back(c.reference_name);
  for (const auto& o : c.outputs)
    names.push_back(o.name);
  for (const auto& [col, from] : c.noise_free)
    names.push_back(col);
  for (const auto& n : names) {
    if (m.symbols.find(n) >= 0) continue;  // a name of the filter's (an input, say) keeps its own
    if (!is_identifier(n) || is_reserved_name(n)) {
      return p.error(std::string(kKey), quote_token(n) + " is not a name");
    }
    m.loop_columns.emplace_back(m.symbols.add(n, kTruthSymbol), n);
  }
  return Ok{};
}

}  // namespace

Expected<std::shared_ptr<const ControllerSpec>> parse_controller(const json& model,
                                                                 const ParamTable& params,
                                                                 ModelSpec& m) {
  auto out = std::make_shared<ControllerSpec>();
  Reader fp(m.path, m.symbols);
  const json& c = model.at("controller");
  if (!c.is_object()) return fp.error(kKey, "expected an object");
  if (auto st = fp.only_keys(
          c, kKey,
          {"description", "reference", "states", "expressions", "outputs", "loop", "noise_free"});
      !st) {
    return st.err();
  }
  if (!m.world) {
    return fp.error(kKey, "a controller drives a world: declare model.world (the plant)");
  }
  if (m.modes) return fp.error(kKey, "a controller with modes (an IMM) is not supported yet");
  if (m.start_channel >= 0) {
    return fp.error(kKey,
                    "x0 from a channel's first sample cannot start a closed loop (the "
                    "filter runs from the first row)");
  }
  for (const auto& s : m.world->channels) {
    if (s.sensor.outliers) {
      return fp.error("model.world.measurements." + s.name + ".outliers",
                      "outliers are drawn over the whole run: not in a closed loop");
    }
  }
  Reader p(m.path, out->symbols);
  if (auto st = base_symbols(p, c, params, m, *out); !st) return st.err();
  if (auto st = parse_reference(p, c, *out); !st) return st.err();
  if (auto st = parse_outputs(p, c, m, *out); !st) return st.err();
  if (auto st = parse_states(p, c, *out); !st) return st.err();
  if (auto it = c.find("expressions"); it != c.end()) {
    if (auto st = parse_expressions(*it, m.path, out->symbols); !st) {
      std::string msg = st.error();
      const std::string from = "model.expressions", to = "model.controller.expressions";
      if (auto at = msg.find(from); at != std::string::npos) msg.replace(at, from.size(), to);
      return Error{msg};
    }
  }
  if (auto st = compile_all(p, c, *out); !st) return st.err();
  if (auto st = parse_loop(p, c, params, *out); !st) return st.err();
  if (auto st = parse_noise_free(p, c, m, *out); !st) return st.err();
  if (auto st = add_loop_columns(fp, *out, m); !st) return st.err();
  return std::shared_ptr<const ControllerSpec>(std::move(out));
}

bool loop_closed(const ControllerSpec& c, const ParamValues& values) {
  if (c.loop_param.empty()) return true;
  const double v = param(values, c.loop_param);
  const auto i = static_cast<std::size_t>(std::max(0.0, v));
  return i < c.closed_by_choice.size() && c.closed_by_choice[i];
}

}  // namespace kfw::model
