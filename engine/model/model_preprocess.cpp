// Pre-processed measurements (version 2, issue 28; presets/models/README.md, "Pre-processed
// measurements"): a channel's `z` — the components the filter compares, expressions of the
// columns it reads — and x0 from a component of a channel's first sample.
#include <set>

#include "model/model_reader.h"

namespace kfw::model::detail {

namespace {

constexpr KindMask kPreprocessKinds =
    kParamSymbol | kDtSymbol | kTimeSymbol | kInputSymbol | kSubSymbol | kMeasuredSymbol;
constexpr const char* kPreprocessWhat =
    "the channel's columns, inputs, parameters, dt, t and sub-expressions, not states";

// A role's name in the channel's JSON (a string or {"name": ...}); empty when malformed (the
// channel's own parse reports it).
std::string role_name(const json& r) {
  if (r.is_string()) return r.get<std::string>();
  if (r.is_object() && r.contains("name") && r["name"].is_string()) {
    return r["name"].get<std::string>();
  }
  return {};
}

}  // namespace

Status add_column_symbols(const Reader& p, const json& j, ModelSpec& m) {
  auto it = j.find("measurements");
  if (it == j.end() || !it->is_object()) return Ok{};
  for (auto c = it->begin(); c != it->end(); ++c) {
    if (!c->is_object() || !c->contains("z") || !(*c)["roles"].is_array()) continue;
    const std::string key = "model.measurements." + c.key();
    if (m.version < 2) return p.error(key + ".z", "a version-2 key: set \"version\": 2");
    if (m.world_block) {
      return p.error(key + ".z", "a sensor writes its columns: pre-process them in the model");
    }
    const json& roles = (*c)["roles"];
    for (std::size_t i = 0; i < roles.size(); ++i) {
      const std::string name = role_name(roles[i]);
      if (name.empty()) continue;
      if (!is_identifier(name) || is_reserved_name(name)) {
        return p.error(idx(key + ".roles", i),
                       quote_token(name) + ": a channel with z reads its columns by name in its " +
                           "expressions, so each role must be a name (letters, digits and _)");
      }
      if (m.symbols.find(name) >= 0) {
        return p.error(idx(key + ".roles", i),
                       quote_token(name) + " is already a symbol (a parameter, state or input)");
      }
      m.symbols.add(name, kMeasuredSymbol);
    }
  }
  return Ok{};
}

Status check_own_columns(const Reader& p, const Expr& e, const std::string& key, const ModelSpec& m,
                         const ChannelSpec& c) {
  for (int slot : symbols_used(e.text, m.symbols)) {
    if (m.symbols.kinds[static_cast<std::size_t>(slot)] != kMeasuredSymbol) continue;
    bool own = false;
    for (int s : c.column_slots)
      own = own || s == slot;
    if (!own) {
      return p.error(key, "reads the column '" + m.symbols.names[static_cast<std::size_t>(slot)] +
                              "', which channel '" + c.name + "' does not read");
    }
  }
  return Ok{};
}

Status parse_preprocess(const Reader& p, const json& j, const std::string& key, const ModelSpec& m,
                        ChannelSpec& c) {
  auto it = j.find("z");
  if (it == j.end()) {
    c.comps = c.roles;
    return Ok{};
  }
  const std::string zkey = key + ".z";
  if (!it->is_array() || it->empty()) {
    return p.error(zkey, "expected a list of components {\"name\", \"unit\", \"expression\"}");
  }
  for (const auto& r : c.roles)
    c.column_slots.push_back(m.symbols.find(r.name));
  std::set<std::string> names;
  for (std::size_t i = 0; i < it->size(); ++i) {
    const json& e = (*it)[i];
    const std::string ekey = idx(zkey, i);
    if (!e.is_object()) {
      return p.error(ekey, "expected {\"name\", \"unit\", \"angle\", \"expression\"}");
    }
    if (auto st = p.only_keys(e, ekey, {"name", "unit", "angle", "expression"}); !st) return st;
    RoleSpec comp;
    auto nm = p.string(e, "name", ekey, true);
    if (!nm) return nm.err();
    comp.name = *nm;
    if (!is_identifier(comp.name)) {
      return p.error(ekey + ".name", quote_token(comp.name) + " is not a name");
    }
    if (!names.insert(comp.name).second) {
      return p.error(ekey + ".name", quote_token(comp.name) + " names two components");
    }
    auto unit = p.string(e, "unit", ekey, false);
    if (!unit) return unit.err();
    comp.unit = *unit;
    auto a = p.angle(e, ekey);
    if (!a) return a.err();
    comp.angle = *a;
    if (!e.contains("expression")) return p.error(ekey, "missing key 'expression'");
    auto x = p.expr(e["expression"], ekey + ".expression", kPreprocessKinds, kPreprocessWhat);
    if (!x) return x.err();
    if (auto st = check_own_columns(p, *x, ekey + ".expression", m, c); !st) return st;
    c.comps.push_back(comp);
    c.z.push_back(*x);
  }
  if (j.contains("noise_param")) {
    return p.error(key + ".noise_param",
                   "not with z: the pre-processed noise is no longer one column's (not yet)");
  }
  return Ok{};
}

Status resolve_initial_channels(const Reader& p, ModelSpec& m) {
  for (std::size_t i = 0; i < m.x0.size(); ++i) {
    InitialSpec& init = m.x0[i];
    const std::string& f = init.first_column;
    const auto dot = f.find('.');
    if (f.empty() || dot == std::string::npos) continue;
    const std::string ch = f.substr(0, dot), comp = f.substr(dot + 1);
    for (std::size_t c = 0; c < m.channels.size(); ++c) {
      if (m.channels[c].name != ch) continue;
      const auto& comps = m.channels[c].comps;
      for (std::size_t k = 0; k < comps.size(); ++k) {
        if (comps[k].name == comp) init.first_component = static_cast<int>(k);
      }
      if (init.first_component < 0) {
        std::string known;
        for (const auto& r : comps)
          known += (known.empty() ? "" : ", ") + r.name;
        return p.error(idx("model.x0", i) + ".first", "channel '" + ch + "' has no component '" +
                                                          comp + "' (it has " + known + ")");
      }
      if (m.version < 2) {
        return p.error(idx("model.x0", i) + ".first",
                       "a channel's component is a version-2 form: set \"version\": 2");
      }
      if (m.start_channel >= 0 && m.start_channel != static_cast<int>(c)) {
        return p.error(idx("model.x0", i) + ".first",
                       "the filter starts at one channel's first sample: x0 already reads "
                       "channel '" +
                           m.channels[static_cast<std::size_t>(m.start_channel)].name + "'");
      }
      init.first_channel = static_cast<int>(c);
      init.first_column.clear();
      m.start_channel = static_cast<int>(c);
    }
  }
  return Ok{};
}

}  // namespace kfw::model::detail
