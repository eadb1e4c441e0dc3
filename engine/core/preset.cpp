#include "core/preset.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/dataset.h"
#include "core/scenario.h"

#ifndef KFW_SOURCE_DIR
#define KFW_SOURCE_DIR "."
#endif

namespace kfw {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string line_col(const std::string& text, std::size_t byte) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

const char* scale_name(Scale s) {
  switch (s) {
    case Scale::kLinear:
      return "linear";
    case Scale::kLog:
      return "log";
    case Scale::kInteger:
      return "integer";
    case Scale::kChoice:
      return "choice";
    case Scale::kToggle:
      return "toggle";
  }
  return "linear";
}

}  // namespace

Expected<Preset> parse_preset(const std::string& text, const std::string& path) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    if (auto p = what.find("syntax error"); p != std::string::npos) what = what.substr(p);
    return Error{path + ":" + line_col(text, e.byte == 0 ? 0 : e.byte - 1) +
                 ": invalid JSON: " + what};
  }
  if (!j.is_object()) return Error{path + ": a preset must be a JSON object"};
  auto str = [&](const char* key, std::string& out, bool required) -> Status {
    auto it = j.find(key);
    if (it == j.end() || it->is_null()) {
      if (required) return Error{path + ": missing key '" + key + "'"};
      return Ok{};
    }
    if (!it->is_string()) return Error{path + ": key '" + key + "' must be a string"};
    out = it->get<std::string>();
    return Ok{};
  };
  std::string format;
  if (auto st = str("format", format, true); !st) return Error{st.error()};
  if (format != kPresetFormat) {
    return Error{path + ": key 'format' is '" + format + "', expected '" + kPresetFormat + "'"};
  }
  auto ver = j.find("version");
  if (ver == j.end() || !ver->is_number_integer()) {
    return Error{path + ": key 'version' must be an integer"};
  }
  if (ver->get<int>() != kPresetVersion) {
    return Error{path + ": key 'version' is " + std::to_string(ver->get<int>()) +
                 ", this build reads version " + std::to_string(kPresetVersion)};
  }
  Preset p;
  p.path = path;
  if (auto st = str("scenario", p.scenario, true); !st) return Error{st.error()};
  if (auto st = str("title", p.title, false); !st) return Error{st.error()};
  if (auto st = str("description", p.description, false); !st) return Error{st.error()};
  std::string data;
  if (auto st = str("data", data, false); !st) return Error{st.error()};
  if (!data.empty()) {
    fs::path dp(data);
    if (dp.is_relative() && !path.empty()) dp = fs::path(path).parent_path() / dp;
    p.data_path = dp.lexically_normal().string();
  }
  auto scenario = make_scenario(p.scenario);
  if (!scenario) return Error{path + ": key 'scenario': " + scenario.error()};
  const ParamTable& table = (*scenario)->params();
  p.values = table.defaults();
  auto params = j.find("parameters");
  if (params != j.end()) {
    if (!params->is_object()) return Error{path + ": key 'parameters' must be an object"};
    for (auto it = params->begin(); it != params->end(); ++it) {
      const std::string& key = it.key();
      const std::string where = path + ": parameters." + key;
      const ParamSpec* spec = table.find(key);
      if (!spec) return Error{where + ": unknown parameter for scenario '" + p.scenario + "'"};
      double value = 0.0;
      const json& e = it.value();
      if (e.is_number()) {
        value = e.get<double>();
      } else if (e.is_object()) {
        auto v = e.find("value");
        if (v == e.end()) return Error{where + ": missing 'value'"};
        if (v->is_string() && spec->scale == Scale::kChoice) {
          ParamValues tmp;
          if (auto st = table.apply_assignment(key + "=" + v->get<std::string>(), tmp); !st) {
            return Error{where + ": " + st.error()};
          }
          value = tmp[key];
        } else if (!v->is_number()) {
          return Error{where + ".value: must be a number"};
        } else {
          value = v->get<double>();
        }
        if (auto u = e.find("unit"); u != e.end()) {
          if (!u->is_string() || u->get<std::string>() != spec->unit) {
            return Error{where + ".unit: '" + (u->is_string() ? u->get<std::string>() : u->dump()) +
                         "' does not match the parameter's unit '" + spec->unit + "'"};
          }
        }
        const bool has_min = e.contains("min"), has_max = e.contains("max");
        if (has_min || has_max) {
          double lo = spec->min, hi = spec->max;
          if (has_min) {
            if (!e["min"].is_number()) return Error{where + ".min: must be a number"};
            lo = e["min"].get<double>();
          }
          if (has_max) {
            if (!e["max"].is_number()) return Error{where + ".max: must be a number"};
            hi = e["max"].get<double>();
          }
          if (!(lo < hi) || lo < spec->min || hi > spec->max) {
            std::ostringstream os;
            os << where << ": range [" << lo << ", " << hi << "] must be increasing and inside ["
               << spec->min << ", " << spec->max << "]";
            return Error{os.str()};
          }
          if (lo != spec->min || hi != spec->max) p.ranges[key] = {lo, hi};
        }
      } else {
        return Error{where + ": expected a number or an object with 'value'"};
      }
      if (auto st = table.check(key, value); !st) return Error{path + ": " + st.error()};
      if (auto r = p.ranges.find(key); r != p.ranges.end()) {
        if (value < r->second.first || value > r->second.second) {
          return Error{where + ": value outside the preset's own range"};
        }
      }
      p.values[key] = value;
    }
  }
  return p;
}

Expected<Preset> load_preset(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open preset"};
  std::ostringstream os;
  os << in.rdbuf();
  return parse_preset(os.str(), path);
}

Expected<Preset> default_preset(const std::string& scenario) {
  auto s = make_scenario(scenario);
  if (!s) return Error{s.error()};
  Preset p;
  p.scenario = scenario;
  p.title = (*s)->title();
  p.values = (*s)->params().defaults();
  return p;
}

std::string preset_to_json(const Preset& preset) {
  nlohmann::ordered_json j;
  j["format"] = kPresetFormat;
  j["version"] = kPresetVersion;
  j["scenario"] = preset.scenario;
  j["title"] = preset.title;
  j["description"] = preset.description;
  if (preset.data_path) {
    fs::path dp(*preset.data_path);
    if (!preset.path.empty()) {
      dp = fs::path(*preset.data_path).lexically_relative(fs::path(preset.path).parent_path());
      if (dp.empty()) dp = *preset.data_path;
    }
    j["data"] = dp.string();
  }
  auto scenario = make_scenario(preset.scenario);
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  if (scenario) {
    for (const auto& spec : (*scenario)->params().specs()) {
      nlohmann::ordered_json e;
      auto v = preset.values.find(spec.key);
      e["value"] = v == preset.values.end() ? spec.def : v->second;
      auto r = preset.ranges.find(spec.key);
      e["min"] = r == preset.ranges.end() ? spec.min : r->second.first;
      e["max"] = r == preset.ranges.end() ? spec.max : r->second.second;
      e["unit"] = spec.unit;
      e["scale"] = scale_name(spec.scale);
      e["label"] = spec.label;
      if (!spec.choices.empty()) e["choices"] = spec.choices;
      params[spec.key] = e;
    }
  }
  j["parameters"] = params;
  return j.dump(2) + "\n";
}

Status save_preset(const std::string& path, const Preset& preset) {
  Preset p = preset;
  p.path = path;
  return write_text_file_atomic(path, preset_to_json(p));
}

std::string preset_dir() {
  if (const char* env = std::getenv("KFW_PRESETS"); env && *env) return env;
  return std::string(KFW_SOURCE_DIR) + "/presets";
}

std::string resolve_preset_path(const std::string& name_or_path) {
  std::error_code ec;
  if (fs::is_regular_file(name_or_path, ec)) return name_or_path;
  fs::path candidate = fs::path(preset_dir()) / name_or_path;
  if (candidate.extension() != ".json") candidate += ".json";
  if (fs::is_regular_file(candidate, ec)) return candidate.string();
  return name_or_path;
}

}  // namespace kfw
