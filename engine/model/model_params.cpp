// parse_param_table (model_scenario.h): a model preset's "parameters" block in full form.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/suggest.h"
#include "model/model_scenario.h"

namespace kfw {

using OJson = nlohmann::ordered_json;

namespace {

Expected<Scale> scale_from(const std::string& s, const std::string& where) {
  if (s == "linear") return Scale::kLinear;
  if (s == "log") return Scale::kLog;
  if (s == "integer") return Scale::kInteger;
  if (s == "choice") return Scale::kChoice;
  if (s == "toggle") return Scale::kToggle;
  return Error{where + ".scale: " + quote_token(s) +
               " is not one of linear, log, integer, choice, toggle"};
}

std::string default_group(const std::string& key) {
  if (key.rfind("sim.", 0) == 0) return "Simulator";
  if (key.rfind("ukf.", 0) == 0 || key == "filter") return "Filter";
  return "Model";
}

}  // namespace

Expected<ParamTable> parse_param_table(const OJson& params, const std::string& path) {
  std::vector<ParamSpec> specs;
  if (params.is_null()) return ParamTable(specs);
  if (!params.is_object()) return Error{path + ": parameters: expected an object"};
  for (auto it = params.begin(); it != params.end(); ++it) {
    const std::string where = path + ": parameters." + it.key();
    const OJson& e = it.value();
    if (!e.is_object()) return Error{where + ": expected {\"value\", \"min\", \"max\", ...}"};
    ParamSpec s;
    s.key = it.key();
    auto str = [&](const char* k, std::string& out) -> Status {
      if (!e.contains(k)) return Ok{};
      if (!e[k].is_string()) return Error{where + "." + k + ": expected a string"};
      out = e[k].get<std::string>();
      return Ok{};
    };
    std::string scale = "linear";
    for (auto [k, out] :
         {std::pair{"unit", &s.unit}, std::pair{"label", &s.label}, std::pair{"group", &s.group},
          std::pair{"description", &s.description}, std::pair{"scale", &scale}}) {
      if (auto st = str(k, *out); !st) return st.err();
    }
    if (s.label.empty()) s.label = s.key;
    if (s.group.empty()) s.group = default_group(s.key);
    auto sc = scale_from(scale, where);
    if (!sc) return sc.err();
    s.scale = *sc;
    if (e.contains("decimals")) {
      if (!e["decimals"].is_number_integer())
        return Error{where + ".decimals: expected an integer"};
      s.decimals = e["decimals"].get<int>();
    }
    if (e.contains("choices")) {
      if (!e["choices"].is_array()) return Error{where + ".choices: expected a list of labels"};
      for (const auto& c : e["choices"]) {
        if (!c.is_string()) return Error{where + ".choices: expected a list of labels"};
        s.choices.push_back(c.get<std::string>());
      }
    }
    if (s.scale == Scale::kChoice) {
      if (s.choices.empty()) return Error{where + ": a choice needs \"choices\""};
      s.min = 0;
      s.max = static_cast<double>(s.choices.size() - 1);
    } else if (s.scale == Scale::kToggle) {
      s.min = 0;
      s.max = 1;
    } else {
      for (auto [k, out] : {std::pair{"min", &s.min}, std::pair{"max", &s.max}}) {
        if (!e.contains(k) || !e[k].is_number())
          return Error{where + "." + k + ": expected a number"};
        *out = e[k].get<double>();
      }
      if (!(s.min <= s.max) || !std::isfinite(s.min) || !std::isfinite(s.max)) {
        return Error{where + ": min must not exceed max"};
      }
      if (s.scale == Scale::kLog && !(s.min > 0.0)) {
        return Error{where + ": a log scale needs min > 0"};
      }
    }
    if (!e.contains("value")) return Error{where + ": missing 'value'"};
    const OJson& v = e["value"];
    if (v.is_string() && s.scale == Scale::kChoice) {
      auto c = std::find(s.choices.begin(), s.choices.end(), v.get<std::string>());
      if (c == s.choices.end()) {
        return Error{where + ".value: " + quote_token(v.get<std::string>()) +
                     " is not one of the choices"};
      }
      s.def = static_cast<double>(c - s.choices.begin());
    } else if (v.is_number()) {
      s.def = v.get<double>();
    } else {
      return Error{where + ".value: must be a number"};
    }
    specs.push_back(s);
    ParamTable one({s});
    if (auto st = one.check(s.key, s.def); !st) return Error{where + ": " + st.error()};
  }
  return ParamTable(std::move(specs));
}

}  // namespace kfw
