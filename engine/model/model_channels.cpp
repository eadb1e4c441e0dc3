// A model's channels (presets/models/README.md, "Channels"): roles, H or h, R, every, gates, and
// (version 2, issue 28, "Pre-processed measurements") `z` — the components the filter compares,
// expressions of the columns it reads — with x0 from a component of a channel's first sample;
// and the grid axes' symbols that derived series read (a parameter as its IMM estimate, the
// truth column).
#include <set>

#include "core/limits.h"
#include "core/suggest.h"

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

Expected<ChannelSpec> parse_channel(const Reader& p, const std::string& name, const json& j,
                                    const ModelSpec& m, const ParamTable& params,
                                    std::set<std::string>& roles_seen) {
  const std::string key = "model.measurements." + name;
  ChannelSpec c;
  c.name = name;
  if (!j.is_object()) return p.error(key, "expected an object");
  if (auto st =
          p.only_keys(j, key,
                      {"roles", "label", "z", "H", "h", "R", "every", "gate", "noise_param",
                       "clock", "dropout", "outliers", "outlier_column", "impulses", "missing"});
      !st) {
    return st.err();
  }
  for (const char* k : {"clock", "dropout", "outliers", "impulses"}) {
    if (j.contains(k) && !m.world_block) {
      return p.error(key + "." + k,
                     "a sensor's key: only a world's sensors (model.world."
                     "measurements) have a clock, dropouts, outliers and impulses");
    }
  }
  if (j.contains("missing") && m.world_block) {
    return p.error(
        key + ".missing",
        "a filter channel's key: a world's sensor writes the flag column (impulses.flag), "
        "the filter's channel reads it");
  }
  auto label = p.string(j, "label", key, false, name);
  if (!label) return label.err();
  c.label = *label;
  if (!j.contains("roles") || !j["roles"].is_array() || j["roles"].empty()) {
    return p.error(key + ".roles", "expected a non-empty list of roles (the columns read)");
  }
  for (std::size_t i = 0; i < j["roles"].size(); ++i) {
    const json& r = j["roles"][i];
    const std::string rkey = idx(key + ".roles", i);
    RoleSpec role;
    if (r.is_string()) {
      role.name = r.get<std::string>();
    } else if (r.is_object()) {
      if (auto st = p.only_keys(r, rkey, {"name", "unit", "angle"}); !st) return st.err();
      auto nm = p.string(r, "name", rkey, true);
      if (!nm) return nm.err();
      role.name = *nm;
      auto unit = p.string(r, "unit", rkey, false);
      if (!unit) return unit.err();
      role.unit = *unit;
      auto a = p.angle(r, rkey);
      if (!a) return a.err();
      role.angle = *a;
    } else {
      return p.error(rkey, "expected a role name or {\"name\", \"unit\", \"angle\"}");
    }
    if (role.name.empty() || role.name == "t") {
      return p.error(rkey, "a role needs a name other than the time column 't'");
    }
    if (!roles_seen.insert(role.name).second) {
      return p.error(rkey,
                     "role " + quote_token(role.name) + " is read by another channel or an input");
    }
    c.roles.push_back(role);
  }
  if (c.roles.size() > static_cast<std::size_t>(kMaxChannelSize)) {
    return p.error(key + ".roles",
                   "at most " + std::to_string(kMaxChannelSize) + " components per channel");
  }
  if (auto st = detail::parse_preprocess(p, j, key, m, c); !st) return st.err();
  if (c.size() > kMaxChannelSize) {
    return p.error(key + ".z",
                   "at most " + std::to_string(kMaxChannelSize) + " components per channel");
  }
  const int mdim = c.size(), n = m.n();
  if (j.contains("H") == j.contains("h")) {
    return p.error(key, "declare exactly one of H (linear) or h (nonlinear)");
  }
  if (j.contains("H")) {
    auto H = p.matrix(j["H"], key + ".H", mdim, n, kLinear, kLinearWhat);
    if (!H) return H.err();
    c.H = *H;
  } else {
    c.linear = false;
    const json& h = j["h"];
    if (!h.is_array() || h.size() != static_cast<std::size_t>(mdim)) {
      return p.error(key + ".h", "wrong dimensions: expected a list of " + std::to_string(mdim) +
                                     " expressions, one per role");
    }
    c.H.key = key + ".h (Jacobian)";
    c.H.rows = mdim;
    c.H.cols = n;
    for (std::size_t i = 0; i < h.size(); ++i) {
      auto e = p.expr(h[i], idx(key + ".h", i), kAllSymbols, "");
      if (!e) return e.err();
      c.h.push_back(*e);
      auto d = derivatives(*e, idx(key + ".h", i), m.symbols, m.state_slots);
      if (!d) return d.err();
      c.H.e.insert(c.H.e.end(), d->begin(), d->end());
    }
  }
  if (!j.contains("R")) return p.error(key, "missing key 'R'");
  const KindMask r_kinds = kAllSymbols | (c.preprocessed() ? kMeasuredSymbol : 0u);
  auto R = p.matrix(j["R"], key + ".R", mdim, mdim, r_kinds, "", true);
  if (!R) return R.err();
  c.R = *R;
  for (std::size_t i = 0; i < c.R.e.size() && c.preprocessed(); ++i) {
    if (auto st = detail::check_own_columns(p, c.R.e[i], c.R.key, m, c); !st) return st.err();
  }
  if (auto st = p.symmetric(c.R); !st) return st.err();
  if (auto it = j.find("every"); it != j.end()) {
    if (it->is_number_integer() && it->get<long long>() >= 1) {
      if (it->get<long long>() > static_cast<long long>(limits::kMaxEvery)) {
        return p.error(key + ".every",
                       std::to_string(it->get<long long>()) + " is more than " + "the limit of " +
                           std::to_string(static_cast<long long>(limits::kMaxEvery)) +
                           " steps between updates (docs/limits.md)");
      }
      c.every = static_cast<int>(it->get<long long>());
    } else if (it->is_string()) {
      c.every_param = it->get<std::string>();
      if (!params.find(c.every_param)) {
        std::vector<std::string> names;
        for (const auto& spec : params.specs())
          names.push_back(spec.key);
        return p.error(key + ".every", unknown_message("parameter", c.every_param, names));
      }
    } else {
      return p.error(key + ".every", "expected an integer ≥ 1 or a parameter name");
    }
  }
  if (auto st = detail::parse_gate(p, j, key, m.version, c); !st) return st.err();
  return c;
}

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
    if (!is_identifier(comp.name) || comp.name.size() > limits::kMaxNameChars) {
      return p.error(ekey + ".name", quote_token(comp.name) + " is not a name (letters, digits " +
                                         "and _, at most " + std::to_string(limits::kMaxNameChars) +
                                         " characters)");
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

// The grid axes' parameters (model.modes.grid[a].param; checked when the modes are parsed).
void add_grid_symbols(const json& j, ModelSpec& m) {
  const auto modes = j.find("modes");
  if (modes == j.end() || !modes->is_object() || !modes->contains("grid")) return;
  const json& grid = (*modes)["grid"];
  if (!grid.is_array()) return;
  for (const json& axis : grid) {
    const bool named = axis.is_object() && axis.contains("param") && axis["param"].is_string();
    m.grid_param_slots.push_back(named ? m.symbols.find(axis["param"].get<std::string>()) : -1);
    const bool truth = axis.is_object() && axis.contains("truth") && axis["truth"].is_string();
    const std::string col = truth ? axis["truth"].get<std::string>() : std::string();
    const bool free =
        truth && is_identifier(col) && !is_reserved_name(col) && m.symbols.find(col) < 0;
    m.grid_truth_slots.push_back(free ? m.symbols.add(col, kTruthSymbol) : -1);
  }
}

}  // namespace kfw::model::detail
