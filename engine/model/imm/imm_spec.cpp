#include "model/imm/imm_spec.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>

#include "core/limits.h"
#include "core/suggest.h"
#include "model/model_eval.h"
#include "model/model_reader.h"
#include "model/model_spec.h"

namespace kfw::model {

using nlohmann::json;

double ParamRef::at(const ParamValues& v) const {
  if (key.empty()) return value;
  const auto it = v.find(key);
  return it == v.end() ? value : it->second;
}

RenewalReading RenewalSpec::at(const ParamValues& v) const {
  if (param.empty()) return fixed;
  const auto it = v.find(param);
  if (it == v.end() || !(it->second >= 0.0)) return fixed;
  const auto i = static_cast<std::size_t>(it->second);
  return i < by_choice.size() ? by_choice[i] : fixed;
}

int grid_decimals(const std::vector<double>& values) {
  double step = 0.0;
  for (std::size_t i = 1; i < values.size(); ++i) {
    const double d = std::fabs(values[i] - values[i - 1]);
    if (d > 0.0 && (step == 0.0 || d < step)) step = d;
  }
  if (!(step > 0.0) || !std::isfinite(step)) return -1;
  for (int d = 0; d <= 10; ++d) {
    const double unit = std::pow(10.0, -d);
    bool close = true;
    for (double v : values)
      close = close && std::fabs(std::round(v / unit) * unit - v) <= step / 20.0;
    if (close) return d;
  }
  return -1;
}

std::string grid_value_text(double v, int decimals) {
  if (decimals < 0 || !std::isfinite(v) || std::fabs(v) >= 1e15) return number(v);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s = buf;
  if (s.find_first_not_of("-0.") == std::string::npos && s[0] == '-') s.erase(0, 1);  // "-0.000"
  return s;
}

void ModesSpec::set_mode_params(const ModelSpec& base, ParamValues& v) const {
  for (const std::string& name : base.mode_params) {
    for (const GridAxisSpec& a : grid) {
      if (a.param == name) v[name] = 0.5 * (a.min.at(v) + a.max.at(v));
    }
  }
}

std::vector<double> ModesSpec::axis_values(double min, double max, int n) {
  if (n <= 1) return {0.5 * (min + max)};
  std::vector<double> g(static_cast<std::size_t>(n));
  for (int a = 0; a < n; ++a)
    g[static_cast<std::size_t>(a)] = min + a * (max - min) / (n - 1);
  return g;
}

Expected<std::vector<Mode>> ModesSpec::modes(const ModelSpec& base, const ParamValues& v) const {
  std::vector<Mode> out;
  if (!is_grid()) {
    for (const ModeSpec& m : list) {
      Mode mode{m.name, m.label, v, m.model ? m.model.get() : &base, {}};
      for (const auto& [key, ref] : m.params)
        mode.values[key] = ref.at(v);
      out.push_back(std::move(mode));
    }
    return out;
  }
  std::vector<std::vector<double>> axes;
  std::size_t count = 1;
  for (const GridAxisSpec& a : grid) {
    const double lo = a.min.at(v), hi = a.max.at(v), n = a.n.at(v);
    if (!(lo <= hi)) {
      return Error{base.path + ": " + a.min.key + " (" + number(lo) + ") must not exceed " +
                   a.max.key + " (" + number(hi) + ")"};
    }
    if (!(n >= 1.0) || n != std::floor(n) || n > static_cast<double>(limits::kMaxModes)) {
      return Error{base.path + ": " + a.n.key + " must be a whole number from 1 to " +
                   std::to_string(limits::kMaxModes) + ", got " + number(n)};
    }
    axes.push_back(axis_values(lo, hi, static_cast<int>(n)));
    count *= axes.back().size();
    if (count > limits::kMaxModes) {
      return Error{base.path + ": model.modes.grid: more than the limit of " +
                   std::to_string(limits::kMaxModes) + " modes (docs/limits.md)"};
    }
  }
  std::vector<int> decimals;
  for (const auto& values : axes)
    decimals.push_back(grid_decimals(values));
  for (std::size_t j = 0; j < count; ++j) {
    Mode mode{"g" + std::to_string(j), "", v, &base, {}};
    std::size_t rest = j;
    for (std::size_t a = 0; a < grid.size(); ++a) {
      const std::size_t i = rest % axes[a].size();
      const double value = axes[a][i];
      rest /= axes[a].size();
      mode.values[grid[a].param] = value;
      mode.grid.push_back(value);
      mode.grid_index.push_back(i);
      mode.label += (a ? ", " : "") + grid[a].label + " = " + grid_value_text(value, decimals[a]);
    }
    out.push_back(std::move(mode));
  }
  return out;
}

namespace detail {

namespace {

std::vector<std::string> keys_of(const ParamTable& params) {
  std::vector<std::string> names;
  for (const auto& s : params.specs())
    names.push_back(s.key);
  return names;
}

// A declared parameter that is a symbol of the model (an identifier key).
Status model_parameter(const Reader& p, const std::string& key, const std::string& name,
                       const ModelSpec& base, const ParamTable& params) {
  for (const auto& k : base.param_keys) {
    if (k == name) return Ok{};
  }
  return p.error(key, unknown_message("parameter of the model", name, base.param_keys) +
                          (params.find(name) ? " (not a name the expressions can use)" : ""));
}

// A number, or the key of a declared parameter.
Expected<ParamRef> param_ref(const Reader& p, const json& j, const std::string& key,
                             const ParamTable& params) {
  if (j.is_number()) {
    const double v = j.get<double>();
    if (!std::isfinite(v)) return p.error(key, "not a finite number");
    return ParamRef{"", v};
  }
  if (!j.is_string()) return p.error(key, "expected a number or a parameter's key");
  const auto name = j.get<std::string>();
  const ParamSpec* s = params.find(name);
  if (!s) return p.error(key, unknown_message("parameter", name, keys_of(params)));
  return ParamRef{name, s->def};
}

// A number gains the parameter `gained_key` (declared ones win); a key follows that parameter.
Expected<ParamRef> gained_ref(const Reader& p, const json& j, const std::string& key,
                              const ParamTable& params, ParamSpec spec, ModesSpec& out) {
  auto r = param_ref(p, j, key, params);
  if (!r) return r.err();
  if (!r->key.empty()) return r;
  if (const ParamSpec* s = params.find(spec.key)) return ParamRef{spec.key, s->def};
  const double v = r->value;
  if (!(v >= spec.min && v <= spec.max)) {
    return p.error(key, number(v) + " is outside the range [" + number(spec.min) + ", " +
                            number(spec.max) + "] of " + spec.key);
  }
  if (spec.scale == Scale::kLog && !(v > 0.0)) spec.scale = Scale::kLinear;
  spec.def = v;
  for (const auto& g : out.gained) {
    if (g.key == spec.key) return ParamRef{spec.key, g.def};
  }
  out.gained.push_back(spec);
  return ParamRef{spec.key, v};
}

// The parameter an axis runs over: a declared one, or a mode parameter (a name the preset does not
// declare: a symbol only the modes set, no slider), whose gained grid keys range over three times
// the axis's span around it.
Expected<ParamSpec> axis_parameter(const Reader& p, const json& a, const std::string& akey,
                                   const std::string& name, const ParamTable& params) {
  if (const ParamSpec* ps = params.find(name)) return *ps;
  ParamSpec ps;
  ps.key = name;
  ps.label = name;
  ps.group = "IMM";
  double lo = 0.0, hi = 0.0;
  for (auto [end, out] : {std::pair{"min", &lo}, std::pair{"max", &hi}}) {
    auto r = a.contains(end)
                 ? param_ref(p, a[end], akey + "." + end, params)
                 : Expected<ParamRef>(p.error(akey, std::string("missing key '") + end + "'"));
    if (!r) return r.err();
    *out = r->key.empty() ? r->value : params.find(r->key)->def;
  }
  // Finite slider ends whatever the axis: ±1e300 at most (an axis at ±1e308 is then refused,
  // naming its key, by the range check of its gained keys).
  constexpr double kEnd = 1e300;
  const double span =
      std::min(std::max({std::fabs(hi - lo), std::fabs(lo), std::fabs(hi), 1e-9}), kEnd);
  ps.min = std::max(std::min(lo, hi) - span, -kEnd);
  ps.max = std::min(std::max(lo, hi) + span, kEnd);
  return ps;
}

Status parse_grid(const Reader& p, const json& j, const ParamTable& params, const ModelSpec& base,
                  ModesSpec& out) {
  const std::string key = "model.modes.grid";
  if (!j.is_array() || j.empty()) return p.error(key, "expected a list of one or more axes");
  std::set<std::string> seen;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string akey = idx(key, i);
    const json& a = j[i];
    if (!a.is_object()) return p.error(akey, "expected {\"param\", \"min\", \"max\", \"n\"}");
    if (auto st = p.only_keys(a, akey, {"param", "min", "max", "n", "label", "truth", "unit"}); !st)
      return st;
    GridAxisSpec ax;
    auto name = p.string(a, "param", akey, true);
    if (!name) return name.err();
    if (auto st = model_parameter(p, akey + ".param", *name, base, params); !st) return st;
    if (!seen.insert(*name).second) return p.error(akey + ".param", "'" + *name + "' twice");
    auto found = axis_parameter(p, a, akey, *name, params);
    if (!found) return found.err();
    const ParamSpec& ps = *found;
    ax.param = *name;
    auto label = p.string(a, "label", akey, false, *name);
    auto truth = p.string(a, "truth", akey, false);
    if (!label) return label.err();
    if (!truth) return truth.err();
    ax.label = *label;
    ax.truth = *truth;
    auto unit = p.string(a, "unit", akey, false, ps.unit);
    if (!unit) return unit.err();
    ax.unit = *unit;
    const std::string g = "grid." + *name + ".";
    for (const char* end : {"min", "max", "n"}) {
      if (!a.contains(end)) return p.error(akey, std::string("missing key '") + end + "'");
      ParamSpec spec{g + end,
                     ps.label + ": grid " + end,
                     ps.unit,
                     ps.min,
                     ps.max,
                     0.0,
                     ps.scale,
                     "IMM",
                     std::string("The ") + end + " of the IMM's grid over " + *name + "."};
      if (std::string(end) == "n") {
        spec = {g + end,
                ps.label + ": grid points",
                "",
                1.0,
                25.0,
                0.0,
                Scale::kInteger,
                "IMM",
                "Grid points over " + *name + " (the modes are the product of the axes)."};
      }
      auto r = gained_ref(p, a[end], akey + "." + end, params, spec, out);
      if (!r) return r.err();
      (std::string(end) == "min" ? ax.min : std::string(end) == "max" ? ax.max : ax.n) = *r;
    }
    out.grid.push_back(std::move(ax));
  }
  return Ok{};
}

// A mode's own model: the base block with its process replaced and its channels' keys patched.
Expected<std::shared_ptr<const ModelSpec>> mode_model(const Reader& p, const json& mode,
                                                      const std::string& mkey, const json& model,
                                                      const ParamTable& params,
                                                      const ModelSpec& base) {
  json patched = model;
  for (const char* k : {"modes", "world", "plots", "derived", "filter"})
    patched.erase(k);
  if (mode.contains("process")) patched["process"] = mode["process"];
  if (auto it = mode.find("measurements"); it != mode.end()) {
    if (!it->is_object()) return p.error(mkey + ".measurements", "expected {\"CHANNEL\": {...}}");
    for (auto c = it->begin(); c != it->end(); ++c) {
      const std::string ckey = mkey + ".measurements." + truncate_token(c.key());
      if (!patched["measurements"].contains(c.key())) {
        std::vector<std::string> names;
        for (const auto& ch : base.channels)
          names.push_back(ch.name);
        return p.error(ckey, unknown_message("channel", c.key(), names));
      }
      if (!c->is_object()) return p.error(ckey, "expected an object of the channel's keys");
      if (auto st = p.only_keys(*c, ckey, {"H", "h", "R"}); !st) return st.err();
      json& ch = patched["measurements"][c.key()];
      if (c->contains("H")) ch.erase("h");
      if (c->contains("h")) ch.erase("H");
      for (auto e = c->begin(); e != c->end(); ++e)
        ch[e.key()] = e.value();
    }
  }
  auto m = parse_model(patched, params, base.path);
  if (!m) {
    // "PATH: model.process.F…" is this mode's "PATH: model.modes.list[i].process.F…".
    std::string what = m.error();
    const std::string from = base.path + ": model.";
    if (what.rfind(from, 0) == 0) what = base.path + ": " + mkey + "." + what.substr(from.size());
    return Error{what};
  }
  return std::shared_ptr<const ModelSpec>(std::make_shared<ModelSpec>(std::move(*m)));
}

Status parse_list(const Reader& p, const json& j, const json& model, const ParamTable& params,
                  const ModelSpec& base, ModesSpec& out) {
  const std::string key = "model.modes.list";
  if (!j.is_array() || j.size() < 2) return p.error(key, "expected a list of two or more modes");
  if (j.size() > limits::kMaxModes) {
    return p.error(key, std::to_string(j.size()) + " modes: more than the limit of " +
                            std::to_string(limits::kMaxModes) + " (docs/limits.md)");
  }
  std::set<std::string> names;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string mkey = idx(key, i);
    const json& m = j[i];
    if (!m.is_object()) return p.error(mkey, "expected {\"name\", \"params\", ...}");
    if (auto st = p.only_keys(m, mkey, {"name", "label", "params", "process", "measurements"}); !st)
      return st;
    ModeSpec mode;
    auto name = p.string(m, "name", mkey, true);
    if (!name) return name.err();
    if (!is_identifier(*name))
      return p.error(mkey + ".name", "a mode's name is a name (letters, digits and _)");
    if (!names.insert(*name).second) return p.error(mkey + ".name", "'" + *name + "' twice");
    auto label = p.string(m, "label", mkey, false, *name);
    if (!label) return label.err();
    mode.name = *name;
    mode.label = *label;
    if (auto it = m.find("params"); it != m.end()) {
      if (!it->is_object()) return p.error(mkey + ".params", "expected {\"PARAMETER\": value}");
      for (auto e = it->begin(); e != it->end(); ++e) {
        const std::string ekey = mkey + ".params." + truncate_token(e.key());
        if (auto st = model_parameter(p, ekey, e.key(), base, params); !st) return st;
        auto r = param_ref(p, e.value(), ekey, params);
        if (!r) return r.err();
        mode.params.emplace_back(e.key(), *r);
      }
    }
    if (m.contains("process") || m.contains("measurements")) {
      auto mm = mode_model(p, m, mkey, model, params, base);
      if (!mm) return mm.err();
      if ((*mm)->states.size() != base.states.size()) return p.error(mkey, "changes the states");
      mode.model = std::move(*mm);
    }
    out.list.push_back(std::move(mode));
  }
  return Ok{};
}

Status parse_markov(const Reader& p, const json& j, const ParamTable& params, ModesSpec& out) {
  const std::string key = "model.modes.markov";
  const ParamSpec stay{"markov.stay",
                       "Markov stay probability",
                       "",
                       0.0,
                       1.0,
                       0.95,
                       Scale::kLinear,
                       "IMM",
                       "p^jj: the probability that the mode stays from one row to the next; the "
                       "rest is spread equally over the other modes.",
                       4};
  if (j.is_null()) {
    auto r = gained_ref(p, json(0.95), key + ".stay", params, stay, out);
    if (!r) return r.err();
    out.stay = *r;
    return Ok{};
  }
  if (!j.is_object() || j.size() != 1 || !(j.contains("stay") || j.contains("matrix")))
    return p.error(key, "expected {\"stay\": p} or {\"matrix\": [[...], ...]}");
  if (j.contains("stay")) {
    auto r = gained_ref(p, j["stay"], key + ".stay", params, stay, out);
    if (!r) return r.err();
    out.stay = *r;
    return Ok{};
  }
  if (out.is_grid()) return p.error(key + ".matrix", "a grid's chain is {\"stay\": p}");
  const std::size_t r = out.list.size();
  const json& m = j["matrix"];
  const std::string mkey = key + ".matrix";
  if (!m.is_array() || m.size() != r)
    return p.error(mkey, "expected " + std::to_string(r) + " rows, one per mode");
  for (std::size_t i = 0; i < r; ++i) {
    if (!m[i].is_array() || m[i].size() != r)
      return p.error(idx(mkey, i), "expected " + std::to_string(r) + " numbers");
    std::vector<double> row;
    double sum = 0.0;
    for (std::size_t c = 0; c < r; ++c) {
      const json& e = m[i][c];
      if (!e.is_number() || !(e.get<double>() >= 0.0 && e.get<double>() <= 1.0))
        return p.error(idx(idx(mkey, i), c), "expected a probability (a number in [0, 1])");
      row.push_back(e.get<double>());
      sum += row.back();
    }
    if (std::abs(sum - 1.0) > 1e-9)
      return p.error(idx(mkey, i), "sums to " + number(sum) + ", not 1");
    out.matrix.push_back(std::move(row));
  }
  return Ok{};
}

Status parse_mu0(const Reader& p, const json& j, ModesSpec& out) {
  const std::string key = "model.modes.mu0";
  if (j.is_null() || (j.is_string() && j.get<std::string>() == "uniform")) return Ok{};
  if (out.is_grid()) return p.error(key, "a grid starts \"uniform\"");
  if (!j.is_array() || j.size() != out.list.size())
    return p.error(key, "expected \"uniform\" or " + std::to_string(out.list.size()) + " numbers");
  double sum = 0.0;
  for (std::size_t i = 0; i < j.size(); ++i) {
    if (!j[i].is_number() || !(j[i].get<double>() >= 0.0) || !std::isfinite(j[i].get<double>()))
      return p.error(idx(key, i), "expected a non-negative number");
    out.mu0.push_back(j[i].get<double>());
    sum += out.mu0.back();
  }
  if (!(sum > 0.0)) return p.error(key, "every entry is 0");
  // Relative to the largest first: entries near the largest double would make the sum infinite.
  const double top = *std::max_element(out.mu0.begin(), out.mu0.end());
  sum = 0.0;
  for (double& m : out.mu0)
    sum += (m /= top);
  for (double& m : out.mu0)
    m /= sum;
  return Ok{};
}

const char* const kReadings[] = {"index", "slope", "rate", "mix"};

Expected<RenewalReading> reading(const Reader& p, const std::string& key, const std::string& name) {
  for (int i = 0; i < 4; ++i) {
    if (name == kReadings[i]) return static_cast<RenewalReading>(i);
  }
  return p.error(key, "'" + name + "' is not a reading of renewal (index, slope, rate, mix)");
}

// "renewal": {"gain", "start", "mode"}: gain and start numbers gain Kp and renewal.start; mode a
// reading or the key of a choice parameter whose labels are readings.
Status parse_renewal(const Reader& p, const json& j, const ParamTable& params, ModesSpec& out) {
  const std::string key = "model.modes.renewal";
  if (!out.is_grid()) return p.error(key, "renewal moves a grid: declare \"grid\"");
  if (!j.is_object()) return p.error(key, "expected {\"gain\", \"start\", \"mode\"}");
  if (auto st = p.only_keys(j, key, {"gain", "start", "mode"}); !st) return st;
  auto r = std::make_shared<RenewalSpec>();
  const ParamSpec kp{"Kp",
                     "Kp, renewal gain",
                     "",
                     0.0,
                     1.0,
                     0.0,
                     Scale::kLinear,
                     "IMM",
                     "Mode-parameter renewal (seed 001 eq. 4): the grid moves by Kp (R̂ − centre) "
                     "every row (per second for the rate reading); 0: the grid stays."};
  const ParamSpec start{"renewal.start",
                        "renewal start",
                        "s",
                        0.0,
                        1e4,
                        0.0,
                        Scale::kLinear,
                        "IMM",
                        "The time (s after the first row) from which the grid moves."};
  auto gain =
      gained_ref(p, j.contains("gain") ? j["gain"] : json(0.0), key + ".gain", params, kp, out);
  if (!gain) return gain.err();
  auto from = gained_ref(p, j.contains("start") ? j["start"] : json(0.0), key + ".start", params,
                         start, out);
  if (!from) return from.err();
  r->gain = *gain;
  r->start = *from;
  if (auto it = j.find("mode"); it != j.end()) {
    if (!it->is_string()) return p.error(key + ".mode", "expected a reading or a choice parameter");
    const auto name = it->get<std::string>();
    if (const ParamSpec* c = params.find(name)) {
      if (c->scale != Scale::kChoice) {
        return p.error(key + ".mode", "'" + name + "' is not a choice parameter");
      }
      r->param = name;
      for (const auto& label : c->choices) {
        auto rd = reading(p, key + ".mode", label);
        if (!rd) return rd.err();
        r->by_choice.push_back(*rd);
      }
    } else {
      auto rd = reading(p, key + ".mode", name);
      if (!rd) return rd.err();
      r->fixed = *rd;
    }
  }
  out.renewal = std::move(r);
  return Ok{};
}

// What an IMM does not run yet: angle states, gates, stacked or sequential groups.
Status check_supported(const Reader& p, const ModelSpec& base) {
  for (const auto& st : base.states) {
    if (st.angle != Angle::kNone) {
      return p.error("model.states", "the angle state '" + st.name +
                                         "' cannot be mixed across modes yet (its mean would "
                                         "not wrap)");
    }
  }
  for (const auto& c : base.channels) {
    if (c.has_gate()) {
      return p.error("model.measurements." + c.name + ".gate",
                     "a gate cannot be combined with modes yet");
    }
  }
  for (const auto& g : base.groups) {
    if (g.scheme != GroupScheme::kEach || !g.scheme_param.empty()) {
      return p.error("model.groups." + g.name,
                     "a stacked or sequential group cannot be combined with modes yet");
    }
  }
  return Ok{};
}

}  // namespace

Expected<std::shared_ptr<const ModesSpec>> parse_modes(const Reader& p, const json& model,
                                                       const ParamTable& params,
                                                       const ModelSpec& base) {
  const json& j = model["modes"];
  const std::string key = "model.modes";
  if (!j.is_object()) return p.error(key, "expected {\"list\" or \"grid\", \"markov\", \"mu0\"}");
  if (auto st = p.only_keys(j, key, {"list", "grid", "markov", "mu0", "renewal", "structure"}); !st)
    return st.err();
  if (j.contains("list") == j.contains("grid"))
    return p.error(key, "expected one of \"list\" (named modes) or \"grid\" (axes)");
  if (auto st = check_supported(p, base); !st) return st.err();
  auto out = std::make_shared<ModesSpec>();
  if (j.contains("grid")) {
    if (auto st = parse_grid(p, j["grid"], params, base, *out); !st) return st.err();
  } else if (auto st = parse_list(p, j["list"], model, params, base, *out); !st) {
    return st.err();
  }
  if (auto st = parse_markov(p, j.contains("markov") ? j["markov"] : json(), params, *out); !st)
    return st.err();
  if (auto st = parse_mu0(p, j.contains("mu0") ? j["mu0"] : json(), *out); !st) return st.err();
  if (j.contains("renewal")) {
    if (auto st = parse_renewal(p, j["renewal"], params, *out); !st) return st.err();
  }
  if (j.contains("structure")) {
    if (auto st = parse_structure(p, j["structure"], params, base, *out); !st) return st.err();
  }
  return std::shared_ptr<const ModesSpec>(std::move(out));
}

}  // namespace detail

}  // namespace kfw::model
