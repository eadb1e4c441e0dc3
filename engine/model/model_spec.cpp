#include "model/model_spec.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>

#include "core/suggest.h"

namespace kfw::model {

using nlohmann::json;

namespace {

// What each place in the model may use, for compile_expr and its messages.
constexpr KindMask kParamsOnly = kParamSymbol;
constexpr KindMask kLinear = kParamSymbol | kDtSymbol | kTimeSymbol;
constexpr KindMask kInputSim = kParamSymbol | kTimeSymbol;
constexpr const char* kParamsOnlyWhat = "parameters only";
constexpr const char* kLinearWhat =
    "parameters, dt and t: a matrix of a linear model cannot depend on states or inputs; "
    "declare f or h instead";
constexpr const char* kInputSimWhat = "parameters and t";

std::string idx(const std::string& key, std::size_t i) {
  return key + "[" + std::to_string(i) + "]";
}

std::string number_text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// "unknown key (did you mean 'measurements'?)", or the known keys when none is near.
std::string unknown_key(const std::string& word, std::initializer_list<const char*> known) {
  const std::vector<std::string> keys(known.begin(), known.end());
  if (auto near = nearest(word, keys)) return "unknown key (did you mean '" + *near + "'?)";
  std::string list;
  for (const auto& k : keys)
    list += (list.empty() ? "" : ", ") + k;
  return "unknown key (known: " + list + ")";
}

std::string size_text(int r, int c) {
  return std::to_string(r) + "×" + std::to_string(c);
}

class Reader {
 public:
  Reader(std::string path, Symbols& symbols) : path_(std::move(path)), symbols_(symbols) {}

  Error error(const std::string& key, const std::string& what) const {
    return Error{path_ + ": " + key + ": " + what};
  }

  Expected<Expr> expr(const json& j, const std::string& key, KindMask allowed,
                      const char* what) const {
    std::string text;
    if (j.is_number()) {
      text = number_text(j.get<double>());
    } else if (j.is_string()) {
      text = j.get<std::string>();
    } else {
      return error(key, "expected an expression (a string or a number), got " + j.dump());
    }
    auto e = compile_expr(text, key, symbols_, allowed, what);
    if (!e) return Error{path_ + ": " + e.error()};
    return e;
  }

  // A rows × cols matrix: a list of rows; a flat list is a column (cols == 1) or, when `diag`,
  // the diagonal of a square matrix.
  Expected<MatrixSpec> matrix(const json& j, const std::string& key, int rows, int cols,
                              KindMask allowed, const char* what, bool diag = false) const {
    MatrixSpec m;
    m.key = key;
    m.rows = rows;
    m.cols = cols;
    if (!j.is_array()) return error(key, "expected a matrix (a list of rows), got " + j.dump());
    const bool flat =
        !j.empty() && std::none_of(j.begin(), j.end(), [](const json& e) { return e.is_array(); });
    const auto n = static_cast<std::size_t>(rows);
    if (flat && (cols == 1 || (diag && rows == cols))) {
      if (j.size() != n) {
        return error(key, "wrong dimensions: expected " + std::to_string(rows) +
                              (cols == 1 ? " entries (a column)" : " diagonal entries") + ", got " +
                              std::to_string(j.size()));
      }
      m.e.assign(n * static_cast<std::size_t>(cols), Expr{"0", Dep::kConst, 0.0});
      for (std::size_t i = 0; i < n; ++i) {
        auto e = expr(j[i], idx(key, i), allowed, what);
        if (!e) return e.err();
        m.e[i * static_cast<std::size_t>(cols) + (cols == 1 ? 0 : i)] = *e;
      }
      return m;
    }
    if (auto st = dimensions(j, key, rows, cols, flat); !st) return st.err();
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < static_cast<std::size_t>(cols); ++c) {
        auto e = expr(j[i][c], idx(idx(key, i), c), allowed, what);
        if (!e) return e.err();
        m.e.push_back(*e);
      }
    }
    return m;
  }

  // A list of rows has the shape rows × cols; else the message says how it differs: the count
  // of rows (and their common length), or the first row (counted from 0, as in KEY[i][j]) that
  // is not a list or has the wrong length.
  Status dimensions(const json& j, const std::string& key, int rows, int cols, bool flat) const {
    const auto n = static_cast<std::size_t>(rows), m = static_cast<std::size_t>(cols);
    const auto wrong = [&](const json& r) { return !r.is_array() || r.size() != m; };
    if (j.size() == n && std::none_of(j.begin(), j.end(), wrong)) return Ok{};
    const std::string expected = "wrong dimensions: expected " + size_text(rows, cols) + ", ";
    const bool same = !j.empty() && std::all_of(j.begin(), j.end(), [&](const json& r) {
      return r.is_array() && r.size() == j[0].size();
    });
    const std::string got = "got " + std::to_string(j.size()) + " rows";
    if (flat) return error(key, expected + got + " of single entries");
    if (j.size() != n || same) {
      return error(key, expected + got + (same ? " of " + std::to_string(j[0].size()) : ""));
    }
    const auto row = static_cast<std::size_t>(std::find_if(j.begin(), j.end(), wrong) - j.begin());
    const json& r = j[row];
    return error(
        key, expected + idx(key, row) +
                 (r.is_array()
                      ? " has " + std::to_string(r.size()) + (r.size() == 1 ? " entry" : " entries")
                      : " is not a row (a list of " + std::to_string(cols) + " entries)"));
  }

  // A covariance: square, symmetric (symbolically, by GiNaC).
  Status symmetric(const MatrixSpec& m) const {
    for (int i = 0; i < m.rows; ++i) {
      for (int j = i + 1; j < m.cols; ++j) {
        if (!same_function(m.at(i, j), m.at(j, i), symbols_)) {
          const auto key = [&](int a, int b) {
            return idx(idx(m.key, static_cast<std::size_t>(a)), static_cast<std::size_t>(b));
          };
          return error(m.key, "not symmetric: " + key(i, j) + " = \"" + m.at(i, j).text +
                                  "\" but " + key(j, i) + " = \"" + m.at(j, i).text + "\"");
        }
      }
    }
    return Ok{};
  }

  Expected<Angle> angle(const json& obj, const std::string& key) const {
    auto it = obj.find("angle");
    if (it == obj.end() || it->is_null() || (it->is_boolean() && !it->get<bool>())) {
      return Angle::kNone;
    }
    if (it->is_string() && it->get<std::string>() == "rad") return Angle::kRad;
    if (it->is_string() && it->get<std::string>() == "deg") return Angle::kDeg;
    return error(key + ".angle", "expected \"rad\" or \"deg\", got " + it->dump());
  }

  Status only_keys(const json& obj, const std::string& key,
                   std::initializer_list<const char*> known) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (std::none_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; })) {
        return error(key + "." + truncate_token(it.key()), unknown_key(it.key(), known));
      }
    }
    return Ok{};
  }

  Expected<std::string> string(const json& obj, const char* name, const std::string& key,
                               bool required, std::string def = {}) const {
    auto it = obj.find(name);
    if (it == obj.end() || it->is_null()) {
      if (required) return error(key, std::string("missing key '") + name + "'");
      return def;
    }
    if (!it->is_string()) return error(key + "." + name, "expected a string");
    return it->get<std::string>();
  }

 private:
  std::string path_;
  Symbols& symbols_;
};

std::vector<std::string> state_names(const ModelSpec& m) {
  std::vector<std::string> names;
  for (const auto& s : m.states)
    names.push_back(s.name);
  return names;
}

// A new symbol name must be an identifier, not reserved, not yet taken.
Status check_name(const Reader& p, const Symbols& symbols, const std::string& name,
                  const std::string& key) {
  if (!is_identifier(name)) {
    return p.error(key,
                   quote_token(name) + " is not a name (letters, digits and _, not first a digit)");
  }
  if (is_reserved_name(name)) return p.error(key, quote_token(name) + " is reserved");
  if (symbols.find(name) >= 0) return p.error(key, quote_token(name) + " is already a symbol");
  return Ok{};
}

Status parse_process(const Reader& p, const json& j, ModelSpec& m) {
  const std::string key = "model.process";
  if (!j.is_object()) return p.error(key, "expected an object");
  if (auto st = p.only_keys(j, key, {"F", "B", "Q", "f", "A", "G", "Qc"}); !st) return st;
  const int n = m.n(), nu = static_cast<int>(m.inputs.size());
  const bool has_f = j.contains("f"), has_F = j.contains("F"), has_A = j.contains("A");
  if (has_f + has_F + has_A != 1) {
    return p.error(key, "declare exactly one of F (linear), A (continuous) or f (nonlinear)");
  }
  ProcessSpec& pr = m.process;
  auto need = [&](const char* name) -> Expected<const json*> {
    if (!j.contains(name)) return p.error(key, std::string("missing key '") + name + "'");
    return &j.at(name);
  };
  if (j.contains("B")) {
    if (nu == 0) return p.error(key + ".B", "the model declares no inputs");
    if (has_f) return p.error(key + ".B", "a nonlinear model uses the inputs in f");
  }
  if (has_A) {
    pr.form = ProcessForm::kContinuous;
    if (j.contains("Q")) return p.error(key + ".Q", "the continuous form takes Qc, not Q");
    auto A = p.matrix(j["A"], key + ".A", n, n, kParamsOnly, kParamsOnlyWhat);
    if (!A) return A.err();
    pr.A = *A;
    if (j.contains("B")) {
      auto B = p.matrix(j["B"], key + ".B", n, nu, kParamsOnly, kParamsOnlyWhat);
      if (!B) return B.err();
      pr.Bc = *B;
    }
    int q = n;
    if (j.contains("G")) {
      const json& g = j["G"];
      q = g.is_array() && !g.empty() && g[0].is_array() ? static_cast<int>(g[0].size()) : 1;
      auto G = p.matrix(g, key + ".G", n, q, kParamsOnly, kParamsOnlyWhat);
      if (!G) return G.err();
      pr.G = *G;
    }
    auto qc = need("Qc");
    if (!qc) return qc.err();
    auto Qc = p.matrix(**qc, key + ".Qc", q, q, kParamsOnly, kParamsOnlyWhat, true);
    if (!Qc) return Qc.err();
    pr.Qc = *Qc;
    return p.symmetric(pr.Qc);
  }
  if (j.contains("G") || j.contains("Qc")) {
    return p.error(key, "G and Qc belong to the continuous form (with A)");
  }
  auto q = need("Q");
  if (!q) return q.err();
  auto Q = p.matrix(**q, key + ".Q", n, n, kAllSymbols, "", true);
  if (!Q) return Q.err();
  pr.Q = *Q;
  if (auto st = p.symmetric(pr.Q); !st) return st;
  if (has_F) {
    pr.form = ProcessForm::kLinear;
    auto F = p.matrix(j["F"], key + ".F", n, n, kLinear, kLinearWhat);
    if (!F) return F.err();
    pr.F = *F;
    if (j.contains("B")) {
      auto B = p.matrix(j["B"], key + ".B", n, nu, kLinear, kLinearWhat);
      if (!B) return B.err();
      pr.B = *B;
    }
    return Ok{};
  }
  pr.form = ProcessForm::kNonlinear;
  const json& f = j["f"];
  if (!f.is_array() || f.size() != static_cast<std::size_t>(n)) {
    return p.error(key + ".f", "wrong dimensions: expected a list of " + std::to_string(n) +
                                   " expressions, one per state");
  }
  pr.F.key = key + ".f (Jacobian)";
  pr.F.rows = pr.F.cols = n;
  for (std::size_t i = 0; i < f.size(); ++i) {
    auto e = p.expr(f[i], idx(key + ".f", i), kAllSymbols, "");
    if (!e) return e.err();
    pr.f.push_back(*e);
    auto d = derivatives(*e, idx(key + ".f", i), m.symbols, m.state_slots);
    if (!d) return d.err();
    pr.F.e.insert(pr.F.e.end(), d->begin(), d->end());
  }
  return Ok{};
}

Expected<ChannelSpec> parse_channel(const Reader& p, const std::string& name, const json& j,
                                    const ModelSpec& m, const ParamTable& params,
                                    std::set<std::string>& roles_seen) {
  const std::string key = "model.measurements." + name;
  ChannelSpec c;
  c.name = name;
  if (!j.is_object()) return p.error(key, "expected an object");
  if (auto st = p.only_keys(j, key, {"roles", "label", "H", "h", "R", "every", "gate"}); !st) {
    return st.err();
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
  if (c.size() > kMaxChannelSize) {
    return p.error(key + ".roles",
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
  auto R = p.matrix(j["R"], key + ".R", mdim, mdim, kAllSymbols, "", true);
  if (!R) return R.err();
  c.R = *R;
  if (auto st = p.symmetric(c.R); !st) return st.err();
  if (auto it = j.find("every"); it != j.end()) {
    if (it->is_number_integer() && it->get<long long>() >= 1) {
      c.every = static_cast<int>(std::min<long long>(it->get<long long>(), 1 << 30));
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
  if (auto it = j.find("gate"); it != j.end()) {
    if (!it->is_number() || !(it->get<double>() > 0.0 && it->get<double>() < 1.0)) {
      return p.error(key + ".gate", "expected a χ² probability in (0, 1), e.g. 0.999");
    }
    c.gate = it->get<double>();
  }
  return c;
}

// "primary": a state, or a non-empty list of distinct states (default: the first state).
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

}  // namespace

Dep MatrixSpec::dep() const {
  Dep d = Dep::kConst;
  for (const auto& x : e)
    d = std::max(d, x.dep);
  return d;
}

bool ModelSpec::linear() const {
  if (process.form == ProcessForm::kNonlinear) return false;
  return std::all_of(channels.begin(), channels.end(), [](const auto& c) { return c.linear; });
}

bool ModelSpec::time_invariant() const {
  if (!linear()) return false;
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
  if (spec.linear()) return {"kf", "ekf", "ukf"};
  return {"ekf", "ukf"};
}

Expected<ModelSpec> parse_model(const json& j, const ParamTable& params, const std::string& path) {
  ModelSpec m;
  m.path = path;
  Reader p(path, m.symbols);
  const std::string key = "model";
  if (!j.is_object()) return p.error(key, "expected an object");
  if (auto st = p.only_keys(j, key,
                            {"version", "description", "states", "inputs", "x0", "P0", "process",
                             "measurements", "truth", "primary", "filter"});
      !st) {
    return st.err();
  }
  if (!j.contains("version") || !j["version"].is_number_integer()) {
    return p.error("model.version", "missing or not an integer");
  }
  if (j["version"].get<int>() != kModelVersion) {
    return p.error("model.version", "is " + j["version"].dump() + ", this build reads version " +
                                        std::to_string(kModelVersion));
  }

  // Symbols: the parameters whose keys are names, dt, t, the states, the inputs.
  for (const auto& spec : params.specs()) {
    if (is_identifier(spec.key) && !is_reserved_name(spec.key)) {
      m.param_slots.push_back(m.symbols.add(spec.key, kParamSymbol));
    }
  }
  m.dt_slot = m.symbols.add("dt", kDtSymbol);
  m.t_slot = m.symbols.add("t", kTimeSymbol);

  if (!j.contains("states") || !j["states"].is_array() || j["states"].empty()) {
    return p.error("model.states", "expected a non-empty list of states");
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

  std::set<std::string> roles_seen;
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
        if (auto ok = p.only_keys(u, ukey, {"name", "unit", "label", "sim"}); !ok) return ok.err();
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

  // Initial state and covariance.
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

  if (!j.contains("process")) return p.error(key, "missing key 'process'");
  if (auto st = parse_process(p, j["process"], m); !st) return st.err();

  if (!j.contains("measurements") || !j["measurements"].is_object() || j["measurements"].empty()) {
    return p.error("model.measurements", "expected an object of one or more channels");
  }
  for (auto it = j["measurements"].begin(); it != j["measurements"].end(); ++it) {
    if (!is_identifier(it.key())) {
      return p.error("model.measurements." + it.key(),
                     "a channel name is a name (letters, digits and _)");
    }
    auto c = parse_channel(p, it.key(), it.value(), m, params, roles_seen);
    if (!c) return c.err();
    m.channels.push_back(std::move(*c));
  }

  m.truth.assign(static_cast<std::size_t>(n), std::string());
  if (auto it = j.find("truth"); it != j.end()) {
    if (!it->is_object()) return p.error("model.truth", "expected {\"state\": \"column\", ...}");
    for (auto t = it->begin(); t != it->end(); ++t) {
      const int s = m.state_index(t.key());
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
  return m;
}

}  // namespace kfw::model
