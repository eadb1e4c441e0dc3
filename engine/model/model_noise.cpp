#include "model/model_noise.h"

#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/suggest.h"
#include "model/model_reader.h"

namespace kfw::model {

using nlohmann::json;

namespace {

using detail::idx;
using detail::number_text;
using detail::Reader;

// Parameters already named by a noise_param, with the key that named them.
using Named = std::map<std::string, std::string>;

// The parameter a noise_param names: declared, of a linear or log scale, named once.
Status check_param(const Reader& p, const std::string& at, const std::string& key,
                   const ParamTable& params, Named& named) {
  const ParamSpec* spec = params.find(key);
  if (!spec) {
    std::vector<std::string> names;
    for (const auto& s : params.specs())
      names.push_back(s.key);
    return p.error(at, unknown_message("parameter", key, names));
  }
  if (spec->scale != Scale::kLinear && spec->scale != Scale::kLog) {
    return p.error(at, quote_token(key) +
                           " is not a continuous parameter (a noise level needs a linear or "
                           "log scale)");
  }
  auto [it, fresh] = named.emplace(key, at);
  if (!fresh) return p.error(at, quote_token(key) + " is already set by " + it->second);
  return Ok{};
}

// The key of R's diagonal entry i, as in messages about R.
std::string r_key(const ChannelSpec& c, int i) {
  return idx(idx(c.R.key, static_cast<std::size_t>(i)), static_cast<std::size_t>(i));
}

// R_ii must be a function of parameters and dt that depends on `key` (∂R_ii/∂key ≠ 0, GiNaC).
Status check_depends(const Reader& p, const std::string& at, const ModelSpec& m,
                     const ChannelSpec& c, int i, const std::string& key) {
  const Expr& e = c.R.at(i, i);
  const std::string rkey = r_key(c, i);
  if (e.dep > Dep::kDt) {
    return p.error(at, rkey + " = \"" + e.text +
                           "\" depends on states, inputs or t: the measured variance is one "
                           "number per column (R of parameters and dt only)");
  }
  const int slot = m.symbols.find(key);
  bool depends = false;
  if (slot >= 0 && m.symbols.kinds[static_cast<std::size_t>(slot)] == kParamSymbol) {
    auto d = derivatives(e, rkey, m.symbols, {slot});
    if (!d) return Error{m.path + ": " + d.error()};
    depends = !(d->front().dep == Dep::kConst && d->front().value == 0.0);
  }
  if (!depends) {
    return p.error(at, rkey + " = \"" + e.text + "\" does not depend on " + quote_token(key) +
                           ": name the parameter its noise sets");
  }
  return Ok{};
}

// An input's noise_param: "KEY" (the variance) or {"key": "KEY", "as": "variance"|"sigma"}.
Status parse_input_noise(const Reader& p, const json& u, const std::string& ukey, InputSpec& in,
                         const ParamTable& params, Named& named) {
  const std::string at = ukey + ".noise_param";
  const json& n = u["noise_param"];
  std::string as = "variance";
  if (n.is_string()) {
    in.noise.param = n.get<std::string>();
  } else if (n.is_object()) {
    if (auto st = p.only_keys(n, at, {"key", "as"}); !st) return st.err();
    auto key = p.string(n, "key", at, true);
    if (!key) return key.err();
    in.noise.param = *key;
    auto a = p.string(n, "as", at, false, "variance");
    if (!a) return a.err();
    as = *a;
  } else {
    return p.error(at, "expected a parameter name or {\"key\": NAME, \"as\": \"sigma\"}");
  }
  if (as != "variance" && as != "sigma") {
    return p.error(at + ".as", quote_token(as) + " is not one of variance, sigma");
  }
  in.noise.sigma = as == "sigma";
  return check_param(p, at, in.noise.param, params, named);
}

// A channel's noise_param: one name for every role, or a list of one per role (null: none).
Status parse_channel_noise(const Reader& p, const json& j, const ModelSpec& m, ChannelSpec& c,
                           const ParamTable& params, Named& named) {
  const std::string at = "model.measurements." + c.name + ".noise_param";
  const json& n = j["noise_param"];
  const auto size = static_cast<std::size_t>(c.size());
  if (n.is_string()) {
    c.noise_shared = true;
    c.noise_params.assign(size, n.get<std::string>());
    if (auto st = check_param(p, at, n.get<std::string>(), params, named); !st) return st.err();
    for (int i = 0; i < c.size(); ++i) {
      if (auto st = check_depends(p, at, m, c, i, c.noise_params[0]); !st) return st.err();
    }
    return Ok{};
  }
  if (!n.is_array() || n.size() != size) {
    return p.error(at, "expected a parameter name, or a list of " + std::to_string(size) +
                           " (one per role; null: none)");
  }
  c.noise_params.assign(size, std::string());
  for (std::size_t i = 0; i < size; ++i) {
    if (n[i].is_null()) continue;
    const std::string ai = idx(at, i);
    if (!n[i].is_string()) return p.error(ai, "expected a parameter name or null");
    c.noise_params[i] = n[i].get<std::string>();
    if (auto st = check_param(p, ai, c.noise_params[i], params, named); !st) return st.err();
    if (auto st = check_depends(p, ai, m, c, static_cast<int>(i), c.noise_params[i]); !st) {
      return st.err();
    }
  }
  return Ok{};
}

// The value of `key` that makes Σ_i R_ii (over `roles`) equal to a target: R evaluated by
// muparser with every other parameter at its value and dt the data's median interval.
class ChannelSolver {
 public:
  ChannelSolver(std::shared_ptr<const ModelSpec> spec, std::size_t channel, std::vector<int> roles,
                ParamSpec param, std::string declared)
      : spec_(std::move(spec)),
        channel_(channel),
        roles_(std::move(roles)),
        param_(std::move(param)),
        declared_(std::move(declared)) {}

  Expected<double> operator()(const std::vector<double>& v, const ParamValues& p, double dt) const;

 private:
  bool log() const { return param_.scale == Scale::kLog; }
  double x_of(double u) const { return log() ? std::pow(10.0, u) : u; }
  double u_of(double x) const { return log() ? std::log10(x) : x; }
  std::optional<std::pair<double, double>> bracket(const std::function<double(double)>& g,
                                                   double u0) const;
  Error no_root(const std::function<double(double)>& g, const std::vector<double>& v) const;

  std::shared_ptr<const ModelSpec> spec_;
  std::size_t channel_;
  std::vector<int> roles_;
  ParamSpec param_;
  std::string declared_;  // "model.measurements.NAME.noise_param"
};

// A sign change of g: within the range, the one nearest u0 (a 256-interval grid); else outside
// it, the nearest to the range (steps doubling outward: 12 decades on a log scale, 1000 widths on
// a linear one).
std::optional<std::pair<double, double>> ChannelSolver::bracket(
    const std::function<double(double)>& g, double u0) const {
  const double lo = u_of(param_.min), hi = u_of(param_.max);
  const double w = hi > lo ? hi - lo : std::max(1.0, std::abs(lo));
  const auto change = [](double a, double b) {
    return std::isfinite(a) && std::isfinite(b) && (a == 0.0 || (a < 0.0) != (b < 0.0));
  };
  constexpr int kGrid = 256;
  std::optional<std::pair<double, double>> best;
  double prev_u = lo, prev_g = g(lo);
  for (int k = 1; k <= kGrid && hi > lo; ++k) {
    const double u = lo + (hi - lo) * k / kGrid, gu = g(u);
    const bool nearer = !best || std::abs(0.5 * (prev_u + u) - u0) <
                                     std::abs(0.5 * (best->first + best->second) - u0);
    if (change(prev_g, gu) && nearer) best = std::pair{prev_u, u};
    prev_u = u;
    prev_g = gu;
  }
  if (best) return best;
  const double ext = log() ? 12.0 : 1000.0 * w;
  double up = hi, g_up = g(hi), down = lo, g_down = g(lo);
  for (double step = w / 64.0; step < 2.0 * ext; step *= 2.0) {
    const double u_up = std::min(up + step, hi + ext), u_down = std::max(down - step, lo - ext);
    const double gu = g(u_up), gd = g(u_down);
    if (change(g_up, gu)) return std::pair{up, u_up};
    if (change(g_down, gd)) return std::pair{u_down, down};
    up = u_up;
    g_up = gu;
    down = u_down;
    g_down = gd;
  }
  return std::nullopt;
}

Error ChannelSolver::no_root(const std::function<double(double)>& g,
                             const std::vector<double>& v) const {
  const ChannelSpec& c = spec_->channels[channel_];
  double target = 0.0;
  std::string what, cols;
  for (std::size_t k = 0; k < roles_.size(); ++k) {
    target += v[k];
    what += (k ? " + " : "") + r_key(c, roles_[k]).substr(c.R.key.size() - 1);
    cols += (k ? ", " : "") + c.roles[static_cast<std::size_t>(roles_[k])].name;
  }
  const double at_lo = g(u_of(param_.min)) + target, at_hi = g(u_of(param_.max)) + target;
  return failure(spec_->path + ": " + declared_ + ": no value of " + quote_token(param_.key) +
                 " gives " + what + " = " + number_text(target) + " (the variance measured in " +
                 cols + "); over its range [" + number_text(param_.min) + ", " +
                 number_text(param_.max) + "] it runs from " + number_text(at_lo) + " to " +
                 number_text(at_hi));
}

Expected<double> ChannelSolver::operator()(const std::vector<double>& v, const ParamValues& p,
                                           double dt) const {
  const ModelSpec& s = *spec_;
  const ChannelSpec& c = s.channels[channel_];
  std::vector<double> vars(s.symbols.names.size(), 0.0), r(roles_.size(), 0.0);
  for (std::size_t i = 0; i < s.param_slots.size(); ++i) {
    if (auto it = p.find(s.param_keys[i]); it != p.end())
      vars[static_cast<std::size_t>(s.param_slots[i])] = it->second;
  }
  vars[static_cast<std::size_t>(s.dt_slot)] = dt;
  ExprGroup group;
  for (std::size_t k = 0; k < roles_.size(); ++k)
    group.add(c.R.at(roles_[k], roles_[k]).text, &r[k]);
  if (auto st = group.bind(s.symbols, vars.data()); !st) return Error{s.path + ": " + st.error()};
  double target = 0.0;
  for (double x : v)
    target += x;
  double& x = vars[static_cast<std::size_t>(s.symbols.find(param_.key))];
  const auto g = [&](double u) {
    x = x_of(u);
    group.eval();
    double sum = 0.0;
    for (double rk : r)
      sum += rk;
    return std::isfinite(sum) ? sum - target : std::numeric_limits<double>::quiet_NaN();
  };
  const double value = p.count(param_.key) ? p.at(param_.key) : param_.def;
  auto br = bracket(g, u_of(std::clamp(value, param_.min, param_.max)));
  if (!br) return no_root(g, v);
  // Bisection to the last bit of u.
  double a = br->first, b = br->second, ga = g(a), gb = g(b);
  for (int it = 0; it < 2000 && ga != 0.0 && gb != 0.0; ++it) {
    const double mid = 0.5 * (a + b);
    if (mid <= std::min(a, b) || mid >= std::max(a, b)) break;
    const double gm = g(mid);
    if (!std::isfinite(gm)) break;
    if ((gm < 0.0) == (ga < 0.0)) {
      a = mid;
      ga = gm;
    } else {
      b = mid;
      gb = gm;
    }
  }
  return x_of(std::abs(ga) <= std::abs(gb) ? a : b);
}

NoiseLink input_link(const InputSpec& in, std::size_t i) {
  NoiseLink l;
  l.columns = {in.name};
  l.param = in.noise.param;
  l.declared = idx("model.inputs", i) + ".noise_param";
  const bool sigma = in.noise.sigma;
  l.value = [sigma](const std::vector<double>& v, const ParamValues&, double) -> Expected<double> {
    return sigma ? std::sqrt(v.front()) : v.front();
  };
  return l;
}

}  // namespace

Status parse_noise_params(const json& j, ModelSpec& m, const ParamTable& params, bool world) {
  Reader p(m.path, m.symbols);
  Named named;
  if (auto it = j.find("inputs"); it != j.end() && it->is_array()) {
    for (std::size_t i = 0; i < it->size(); ++i) {
      const json& u = (*it)[i];
      if (!u.is_object() || !u.contains("noise_param")) continue;
      const std::string ukey = idx("model.inputs", i);
      if (world) {
        return p.error(ukey + ".noise_param",
                       "a world's input sets no parameter: link the filter's input");
      }
      if (auto st = parse_input_noise(p, u, ukey, m.inputs[i], params, named); !st) return st;
    }
  }
  for (auto& c : m.channels) {
    const json& cj = j["measurements"][c.name];
    if (!cj.contains("noise_param")) continue;
    if (world) {
      return p.error("model.measurements." + c.name + ".noise_param",
                     "a world's sensor sets no parameter: link the filter's channel");
    }
    if (auto st = parse_channel_noise(p, cj, m, c, params, named); !st) return st;
  }
  return Ok{};
}

std::vector<NoiseLink> noise_links(const std::shared_ptr<const ModelSpec>& spec,
                                   const ParamTable& table) {
  std::vector<NoiseLink> links;
  for (std::size_t i = 0; i < spec->inputs.size(); ++i) {
    if (!spec->inputs[i].noise.param.empty()) links.push_back(input_link(spec->inputs[i], i));
  }
  for (std::size_t ci = 0; ci < spec->channels.size(); ++ci) {
    const ChannelSpec& c = spec->channels[ci];
    const std::string declared = "model.measurements." + c.name + ".noise_param";
    // One link per parameter: every role (one name for all) or each named role.
    std::vector<std::vector<int>> groups;
    if (c.noise_shared) {
      groups.emplace_back();
      for (int r = 0; r < c.size(); ++r)
        groups.back().push_back(r);
    } else {
      for (std::size_t r = 0; r < c.noise_params.size(); ++r) {
        if (!c.noise_params[r].empty()) groups.push_back({static_cast<int>(r)});
      }
    }
    for (const auto& roles : groups) {
      const std::string& key = c.noise_params[static_cast<std::size_t>(roles.front())];
      const ParamSpec* ps = table.find(key);
      if (!ps) continue;  // checked when the model loaded
      NoiseLink l;
      for (int r : roles)
        l.columns.push_back(c.roles[static_cast<std::size_t>(r)].name);
      l.param = key;
      l.declared = c.noise_shared ? declared : idx(declared, static_cast<std::size_t>(roles[0]));
      l.value = ChannelSolver(spec, ci, roles, *ps, l.declared);
      links.push_back(std::move(l));
    }
  }
  return links;
}

}  // namespace kfw::model
