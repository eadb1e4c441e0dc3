// Channel groups and the distance gate (version 2): how seed 004's AS / SC / SI update schemes
// are declared — the scalar range channels grouped, the scheme one choice parameter's alternatives
// — and each range gated on its own S_ii. Parsing, and their values per run; the run itself is
// model_filter_detail.h's and model_filters.h's.
#include <algorithm>
#include <cmath>
#include <set>

#include "model/model_eval.h"
#include "model/model_reader.h"

namespace kfw::model::detail {

namespace {

constexpr const char* kSchemes = "\"each\", \"stacked\" or \"sequential\"";

Expected<GroupScheme> scheme_named(const Reader& p, const json& j, const std::string& key) {
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    if (s == "each") return GroupScheme::kEach;
    if (s == "stacked") return GroupScheme::kStacked;
    if (s == "sequential") return GroupScheme::kSequential;
  }
  return p.error(key, std::string("expected ") + kSchemes + ", got " + truncate_token(j.dump()));
}

// "scheme": a scheme, or {"param": CHOICE, "LABEL": scheme, ...} with every label of the choice.
Status parse_scheme(const Reader& p, const json& j, const std::string& key,
                    const ParamTable& params, GroupSpec& g) {
  if (!j.is_object()) {
    auto s = scheme_named(p, j, key);
    if (!s) return s.err();
    g.scheme = *s;
    return Ok{};
  }
  auto alt = choice_alternatives(p, j, key, params, "alternative");
  if (!alt) return alt.err();
  g.scheme_param = alt->param;
  for (std::size_t c = 0; c < alt->values.size(); ++c) {
    const std::string& label = params.find(alt->param)->choices[c];
    auto s = scheme_named(p, *alt->values[c], key + "." + label);
    if (!s) return s.err();
    g.by_choice.push_back(*s);
  }
  return Ok{};
}

Expected<GroupSpec> parse_group(const Reader& p, const std::string& name, const json& j,
                                const ParamTable& params, const ModelSpec& m,
                                std::set<int>& grouped) {
  const std::string key = "model.groups." + truncate_token(name);
  if (!is_identifier(name)) return p.error(key, "a group's name is a name (letters, digits, _)");
  if (!j.is_object()) return p.error(key, "expected {\"channels\", \"scheme\", \"cross\"}");
  if (auto st = p.only_keys(j, key, {"channels", "scheme", "cross"}); !st) return st.err();
  GroupSpec g;
  g.name = name;
  auto chans = j.find("channels");
  if (chans == j.end() || !chans->is_array() || chans->size() < 2) {
    return p.error(key + ".channels", "expected a list of two or more channel names");
  }
  if (chans->size() > static_cast<std::size_t>(kMaxChannelSize)) {
    return p.error(key + ".channels",
                   "at most " + std::to_string(kMaxChannelSize) + " channels in a group");
  }
  std::vector<std::string> names;
  for (const auto& c : m.channels)
    names.push_back(c.name);
  for (std::size_t i = 0; i < chans->size(); ++i) {
    const std::string ckey = idx(key + ".channels", i);
    if (!(*chans)[i].is_string()) return p.error(ckey, "expected a channel name");
    const std::string c = (*chans)[i].get<std::string>();
    const auto at = std::find(names.begin(), names.end(), c);
    if (at == names.end()) return p.error(ckey, unknown_message("channel", c, names));
    const int ci = static_cast<int>(at - names.begin());
    if (m.channels[static_cast<std::size_t>(ci)].size() != 1) {
      return p.error(ckey, "channel '" + c + "' has " +
                               std::to_string(m.channels[static_cast<std::size_t>(ci)].size()) +
                               " components; a group's members are scalar channels");
    }
    if (m.channels[static_cast<std::size_t>(ci)].preprocessed()) {
      return p.error(ckey, "channel '" + c +
                               "' is pre-processed (z); a group's members are not "
                               "(not yet)");
    }
    if (!grouped.insert(ci).second) {
      return p.error(ckey, "channel '" + c + "' is already in a group");
    }
    g.members.push_back(ci);
  }
  g.cross = Expr{"0", Dep::kConst, 0.0};
  if (auto it = j.find("cross"); it != j.end()) {
    auto e = p.expr(*it, key + ".cross", kParamsOnly, kParamsOnlyWhat);
    if (!e) return e.err();
    g.cross = *e;
  }
  if (auto it = j.find("scheme"); it != j.end()) {
    if (auto st = parse_scheme(p, *it, key + ".scheme", params, g); !st) return st.err();
  } else {
    return p.error(key, "missing key 'scheme' (" + std::string(kSchemes) + ")");
  }
  return g;
}

}  // namespace

Error unknown_choice_parameter(const Reader& p, const std::string& key, const std::string& name,
                               const ParamTable& params) {
  std::vector<std::string> names;
  for (const auto& s : params.specs()) {
    if (s.scale == Scale::kChoice) names.push_back(s.key);
  }
  return p.error(key + ".param", unknown_message("choice parameter", name, names));
}

Expected<ChoiceAlternatives> choice_alternatives(const Reader& p, const json& j,
                                                 const std::string& key, const ParamTable& params,
                                                 const char* what) {
  auto param = p.string(j, "param", key, true);
  if (!param) return param.err();
  const ParamSpec* spec = params.find(*param);
  if (!spec || spec->scale != Scale::kChoice)
    return unknown_choice_parameter(p, key, *param, params);
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it.key() != "param" &&
        std::find(spec->choices.begin(), spec->choices.end(), it.key()) == spec->choices.end()) {
      return p.error(key + "." + truncate_token(it.key()),
                     unknown_message("choice of '" + *param + "'", it.key(), spec->choices));
    }
  }
  ChoiceAlternatives out{*param, {}};
  for (const auto& label : spec->choices) {
    auto it = j.find(label);
    if (it == j.end()) {
      return p.error(
          key, std::string("missing the ") + what + " for '" + *param + "' = '" + label + "'");
    }
    out.values.push_back(&*it);
  }
  return out;
}

Status parse_gate(const Reader& p, const json& j, const std::string& channel_key, int version,
                  ChannelSpec& c) {
  if (auto it = j.find("outlier_column"); it != j.end()) {
    const std::string key = channel_key + ".outlier_column";
    if (version < 2) return p.error(key, "a version-2 key: set \"version\": 2");
    if (!it->is_string() || it->get<std::string>().empty())
      return p.error(key, "expected a column name");
    c.outlier_column = it->get<std::string>();
  }
  auto it = j.find("gate");
  if (it == j.end()) return Ok{};
  const json& g = *it;
  const std::string key = channel_key + ".gate";
  if (g.is_object()) {
    if (version < 2)
      return p.error(key, "{\"sigma\": ...} is a version-2 gate: set \"version\": 2");
    if (auto st = p.only_keys(g, key, {"sigma"}); !st) return st;
    if (!g.contains("sigma")) return p.error(key, "missing key 'sigma'");
    if (c.size() != 1) {
      return p.error(key + ".sigma", "a distance gate applies to a scalar channel; this one has " +
                                         std::to_string(c.size()) +
                                         " components: give a χ² probability");
    }
    auto e = p.expr(g["sigma"], key + ".sigma", kParamsOnly, kParamsOnlyWhat);
    if (!e) return e.err();
    c.gate_sigma = *e;
    return Ok{};
  }
  if (!g.is_number() || !(g.get<double>() > 0.0 && g.get<double>() < 1.0)) {
    return p.error(
        key, "expected a χ² probability in (0, 1), e.g. 0.999, or {\"sigma\": d} (|y| > d·√S)");
  }
  c.gate = g.get<double>();
  return Ok{};
}

Status parse_groups(const Reader& p, const json& groups, const ParamTable& params, ModelSpec& m) {
  if (!groups.is_object()) {
    return p.error("model.groups", "expected {\"NAME\": {\"channels\", \"scheme\", \"cross\"}}");
  }
  std::set<int> grouped;
  for (auto it = groups.begin(); it != groups.end(); ++it) {
    auto g = parse_group(p, it.key(), it.value(), params, m, grouped);
    if (!g) return g.err();
    m.groups.push_back(std::move(*g));
  }
  return Ok{};
}

}  // namespace kfw::model::detail

namespace kfw::model {

Status ModelEval::bind_gates_and_groups(const ParamValues& values) {
  const ModelSpec& s = spec_;
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    const ChannelSpec& cs = s.channels[c];
    if (cs.gate_sigma.text.empty()) continue;
    Channel& ch = channels_[c];
    if (!(ch.gate_sigma > 0.0 && std::isfinite(ch.gate_sigma))) {
      return Error{s.path + ": model.measurements." + cs.name + ".gate.sigma: " +
                   number(ch.gate_sigma) + " at the parameters' values; expected a distance > 0"};
    }
    ch.gate_nis = ch.gate_sigma * ch.gate_sigma;
  }
  for (std::size_t g = 0; g < s.groups.size(); ++g) {
    const GroupSpec& gs = s.groups[g];
    Group& gr = groups_[g];
    const std::string key = s.path + ": model.groups." + gs.name;
    gr.scheme = gs.scheme;
    if (!gs.scheme_param.empty()) {
      const auto it = values.find(gs.scheme_param);
      const double v = it == values.end() ? -1.0 : it->second;
      const auto n = static_cast<double>(gs.by_choice.size());
      if (!(v >= 0.0 && v < n) || v != std::round(v)) {
        return Error{key + ".scheme: parameter '" + gs.scheme_param + "' = " + number(v) +
                     " is not one of its choices"};
      }
      gr.scheme = gs.by_choice[static_cast<std::size_t>(v)];
    }
    if (!std::isfinite(gr.cross)) {
      return Error{key + ".cross: " + number(gr.cross) + " at the parameters' values"};
    }
    if (gr.scheme != GroupScheme::kStacked) continue;
    // The stacked R: the members' variances on the diagonal, `cross` between them.
    const auto m = static_cast<Eigen::Index>(gs.members.size());
    MatX R = MatX::Constant(m, m, gr.cross);
    bool known = true;
    for (Eigen::Index i = 0; i < m; ++i) {
      const auto c = static_cast<std::size_t>(gs.members[static_cast<std::size_t>(i)]);
      known = known && s.channels[c].R.dep() <= Dep::kParam;
      R(i, i) = channels_[c].R(0, 0);
    }
    if (known && !is_psd(R)) {
      return Error{key + ".cross: the stacked R (members' R on the diagonal, cross " +
                   number(gr.cross) + " elsewhere) is not positive semidefinite (smallest " +
                   "eigenvalue " + number(min_eigenvalue(R)) + ")"};
    }
  }
  return Ok{};
}

}  // namespace kfw::model
