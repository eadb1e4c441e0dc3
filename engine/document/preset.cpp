#include "document/preset.h"

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "core/dataset.h"
#include "core/retired.h"
#include "core/scenario.h"
#include "core/suggest.h"
#include "data/csv.h"
#include "data/json_io.h"
#include "document/file_paths.h"

#ifndef KFW_SOURCE_DIR
#define KFW_SOURCE_DIR "."
#endif

namespace kfw {

namespace fs = std::filesystem;
using nlohmann::json;
// Presets are read keeping the file's order of keys: a model file's parameters are its table.
using OJson = nlohmann::ordered_json;

namespace {

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

// The schema (presets/README.md): top-level keys and the keys of a parameter entry.
const std::vector<std::string> kTopKeys = {"format",      "version", "scenario",         "title",
                                           "description", "data",    "parameters",       "mapping",
                                           "model",       "sim",     "default_objective"};
const std::vector<std::string> kParamKeys = {"value",       "min",   "max",         "unit",
                                             "scale",       "label", "choices",     "tunable",
                                             "scale_group", "group", "description", "decimals"};

std::string unknown_key(const std::string& key, const std::vector<std::string>& allowed) {
  if (auto near = nearest(key, allowed)) return "unknown key (did you mean '" + *near + "'?)";
  std::string msg = "unknown key (";
  for (std::size_t i = 0; i < allowed.size(); ++i)
    msg += (i ? ", " : "") + allowed[i];
  return msg + ")";
}

bool allowed(const std::string& key, const std::vector<std::string>& keys) {
  for (const auto& k : keys) {
    if (k == key) return true;
  }
  return false;
}

// Reads one parameter entry into the preset. `where` is "FILE: parameters.KEY".
Status read_parameter(Preset& p, const ParamTable& table, const std::string& key, const OJson& e,
                      const std::string& file) {
  const std::string where = file + ": " + key_path("parameters", key);
  const ParamSpec* spec = table.find(key);
  if (!spec) {
    return Error{where + ": unknown parameter for scenario '" + p.scenario + "'"};
  }
  double value = 0.0;
  ParamMeta& meta = p.meta[key];
  if (e.is_number()) {
    value = e.get<double>();
  } else if (e.is_object()) {
    for (auto it = e.begin(); it != e.end(); ++it) {
      if (!allowed(it.key(), kParamKeys)) {
        return Error{where + "." + truncate_token(it.key()) + ": " +
                     unknown_key(it.key(), kParamKeys)};
      }
    }
    auto v = e.find("value");
    if (v == e.end()) return Error{where + ": missing 'value'"};
    if (v->is_string() && spec->scale == Scale::kChoice) {
      ParamValues tmp;
      if (auto st = table.apply_assignment(key + "=" + v->get<std::string>(), tmp); !st) {
        return Error{where + ".value: " + st.error()};
      }
      value = tmp[key];
    } else if (!v->is_number()) {
      return Error{where + ".value: must be a number, not " + json_type_name(*v)};
    } else {
      value = v->get<double>();
    }
    if (auto u = e.find("unit"); u != e.end()) {
      if (!u->is_string() || u->get<std::string>() != spec->unit) {
        return Error{where + ".unit: '" + (u->is_string() ? u->get<std::string>() : u->dump()) +
                     "' does not match the parameter's unit '" + spec->unit + "'"};
      }
    }
    for (const char* k : {"scale", "label", "scale_group", "group", "description"}) {
      if (auto f = e.find(k); f != e.end() && !f->is_string()) {
        return Error{where + "." + k + ": must be a string, not " + json_type_name(*f)};
      }
    }
    if (auto f = e.find("tunable"); f != e.end()) {
      if (!f->is_boolean()) return Error{where + ".tunable: must be true or false"};
      meta.tunable = f->get<bool>();
    }
    if (auto f = e.find("scale_group"); f != e.end()) meta.scale_group = f->get<std::string>();
    if (auto f = e.find("choices"); f != e.end() && !f->is_array()) {
      return Error{where + ".choices: must be an array of labels"};
    }
    if (auto f = e.find("decimals"); f != e.end() && !f->is_number_integer()) {
      return Error{where + ".decimals: must be a whole number"};
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
    return Error{where + ": expected a number or an object with 'value', not " + json_type_name(e)};
  }
  if (auto st = table.check(key, value); !st) return Error{where + ": " + st.error()};
  if (auto r = p.ranges.find(key); r != p.ranges.end()) {
    if (value < r->second.first || value > r->second.second) {
      return Error{where + ": value outside the preset's own range"};
    }
  }
  p.values[key] = value;
  return Ok{};
}

Expected<Preset> preset_from_json(const OJson& j, const std::string& path);

// A parameter entry's value, for the overlay onto a model file: a number, or an object's "value".
const OJson* entry_value(const OJson& e) {
  if (!e.is_object()) return &e;
  auto v = e.find("value");
  return v == e.end() ? nullptr : &*v;
}

// A preset that names a retired built-in (core/retired.h): the shipped model file with this
// file's title, description, data, mapping, objective, sim flags and values (keys the model file
// lacks dropped and named), read as if this file had been it; one notice says so.
Expected<Preset> retired_from_json(const OJson& j, const std::string& path,
                                   const RetiredScenario& r) {
  const std::string shipped = retired_model_path(r.scenario);
  const std::string what = path + ": scenario '" + std::string(r.scenario) + "' is retired";
  std::error_code ec;
  if (!fs::is_regular_file(shipped, ec)) {
    return Error{what + " and its model file " + shipped +
                 " cannot be found (KFW_PRESETS names the folder of kfw's presets)"};
  }
  auto doc = read_ordered_json_document(shipped, "preset");
  if (!doc) return Error{what + ": " + doc.error()};
  auto m = doc->find("model");
  if (!doc->is_object() || m == doc->end() || doc->value("scenario", "") != "model") {
    return Error{what + ", but " + shipped + " is not a model file"};
  }
  // The file's entries are checked against the model file's table (its keys, units, ranges and
  // types are the built-in's), less the keys the built-in had and the file dropped (retired.h).
  auto base = preset_from_json(*doc, shipped);
  if (!base) return Error{what + ": " + base.error()};
  Preset check;  // the file read against the model file's table: its narrowed ranges
  if (auto old = j.find("parameters"); old != j.end()) {
    if (!old->is_object()) return Error{path + ": parameters: must be an object"};
    check.scenario = r.scenario;
    for (auto it = old->begin(); it != old->end(); ++it) {
      if (r.is_dropped(it.key())) continue;
      auto st = read_parameter(check, base->instance->params(), it.key(), it.value(), path);
      if (!st) return st.err();
    }
  }
  OJson merged = *doc;
  merged["version"] = j.at("version");
  for (const char* key : {"title", "description", "default_objective", "data", "mapping", "sim"}) {
    const bool own = std::string_view(key) == "data" || key == std::string_view("mapping") ||
                     key == std::string_view("sim");  // the file's alone, never the model file's
    if (auto it = j.find(key); it != j.end()) {
      merged[key] = *it;
    } else if (own) {
      merged.erase(key);
    }
  }
  std::vector<std::string> dropped;
  OJson& params = merged["parameters"];
  if (auto old = j.find("parameters"); old != j.end() && old->is_object() && params.is_object()) {
    for (auto it = old->begin(); it != old->end(); ++it) {
      const OJson* v = entry_value(it.value());
      auto target = params.find(it.key());
      if (target == params.end() || !v) {
        dropped.push_back(it.key());
      } else if (target->is_object()) {
        (*target)["value"] = *v;
      } else {
        *target = *v;
      }
    }
  }
  auto p = preset_from_json(merged, path);
  if (!p) return p.err();
  for (const auto& [key, range] : check.ranges) {
    const ParamSpec* spec = p->instance->params().find(key);
    if (spec && spec->min <= range.first && range.second <= spec->max) p->ranges[key] = range;
  }
  p->retired_from = std::string(r.scenario);
  p->dropped_keys = dropped;
  std::string notice = what + ": loaded as the model file " + shipped + " with this file's values";
  if (!dropped.empty()) {
    notice += " (dropped, not in the model file:";
    for (const auto& k : dropped)
      notice += " " + truncate_token(k);
    notice += ")";
  }
  p->notices.push_back(notice + "; kfw-cli upgrade " + path + " rewrites it in the current form");
  return p;
}

Expected<Preset> preset_from_json(const OJson& j, const std::string& path) {
  if (!j.is_object()) return Error{path + ": a preset must be a JSON object"};
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!allowed(it.key(), kTopKeys)) {
      return Error{path + ": " + truncate_token(it.key()) + ": " + unknown_key(it.key(), kTopKeys)};
    }
  }
  auto str = [&](const char* key, std::string& out, bool required) -> Status {
    auto it = j.find(key);
    if (it == j.end() || it->is_null()) {
      if (required) return Error{path + ": " + key + ": missing (required)"};
      return Ok{};
    }
    if (!it->is_string()) {
      return Error{path + ": " + key + ": must be a string, not " + json_type_name(*it)};
    }
    out = it->get<std::string>();
    return Ok{};
  };
  std::string format;
  if (auto st = str("format", format, true); !st) return st.err();
  if (format != kPresetFormat) {
    return Error{path + ": format: '" + format + "', expected '" + kPresetFormat + "'"};
  }
  Preset p;
  p.path = path;
  {
    auto ver = j.find("version");
    if (ver == j.end() || !ver->is_number_integer()) {
      return Error{path + ": version: must be a whole number (1 or 2)"};
    }
    // Compared as the JSON's own integer type: 4294967297 is not 1.
    const bool known = ver->is_number_unsigned()
                           ? (ver->get<std::uint64_t>() == 1 || ver->get<std::uint64_t>() == 2)
                           : (ver->get<std::int64_t>() == 1 || ver->get<std::int64_t>() == 2);
    if (!known) {
      const bool newer = ver->is_number_unsigned() || ver->get<std::int64_t>() > 2;
      return Error{path + ": version: " + ver->dump() + "; this build reads versions 1 and 2" +
                   (newer ? " (written by a newer kfw, version " + ver->dump() + ")" : "")};
    }
    p.version = static_cast<int>(ver->get<std::int64_t>());
  }
  if (auto st = str("scenario", p.scenario, true); !st) return st.err();
  if (const RetiredScenario* r = find_retired(p.scenario); r && !j.contains("model")) {
    return retired_from_json(j, path, *r);
  }
  if (auto st = str("title", p.title, false); !st) return st.err();
  if (auto st = str("description", p.description, false); !st) return st.err();
  std::string data;
  if (auto st = str("data", data, false); !st) return st.err();
  if (!data.empty()) p.data_path = fs::path(path_from_file(data, path)).lexically_normal().string();
  // Scenarios built from the preset itself (a model file) registered as such (core/scenario.h).
  const ScenarioRegistry::PresetFactory* factory = scenarios().from_preset(p.scenario);
  if (auto m = j.find("model"); m != j.end()) {
    // A misspelled "model", most likely (a retired built-in's name is known: the next message).
    if (!factory && !find_retired(p.scenario)) {
      return Error{path +
                   ": scenario: " + unknown_message("scenario", p.scenario, scenarios().names())};
    }
    if (!factory) {
      return Error{path +
                   ": model: only a preset whose scenario is a model may carry a model "
                   "block (scenario is '" +
                   p.scenario + "')"};
    }
    if (!m->is_object()) return Error{path + ": model: must be an object"};
    p.model = *m;
  }
  if (factory) {
    auto s = (*factory)(j, path);
    if (!s) return s.err();
    p.instance = std::shared_ptr<const Scenario>(std::move(*s));
    if (auto params = j.find("parameters"); params != j.end()) p.parameters_block = *params;
  } else {
    return Error{path + ": scenario: " + unknown_scenario(p.scenario)};
  }
  const ParamTable& table = p.instance->params();
  p.values = table.defaults();
  for (const auto& spec : table.specs())
    p.meta[spec.key] = ParamMeta{spec.tunable, spec.scale_group};
  if (auto params = j.find("parameters"); params != j.end()) {
    if (!params->is_object()) return Error{path + ": parameters: must be an object"};
    for (auto it = params->begin(); it != params->end(); ++it) {
      if (auto st = read_parameter(p, table, it.key(), it.value(), path); !st) return st.err();
    }
  }
  if (auto m = j.find("mapping"); m != j.end()) {
    auto mapping = mapping_from_json(*m, "mapping");
    if (!mapping) return Error{path + ": " + mapping.error()};
    p.mapping = std::move(*mapping);
  }
  if (auto st = str("default_objective", p.default_objective, false); !st) return st.err();
  if (!p.default_objective.empty() && !is_combined_objective(p.default_objective) &&
      p.default_objective != "nis" && !is_declared_metric(*p.instance, p.default_objective)) {
    std::vector<std::string> names;
    for (const auto& c : combined_objectives())
      names.emplace_back(c.name);
    for (const auto& k : metric_keys(*p.instance))
      names.push_back(k);
    return Error{
        path + ": default_objective: " + unknown_message("objective", p.default_objective, names)};
  }
  if (auto s = j.find("sim"); s != j.end()) {
    if (!s->is_object()) return Error{path + ": sim: must be an object"};
    for (auto it = s->begin(); it != s->end(); ++it) {
      if (it.key() != "x0_from_prior") {
        return Error{path + ": sim." + truncate_token(it.key()) + ": unknown key (x0_from_prior)"};
      }
      if (!it->is_boolean()) return Error{path + ": sim.x0_from_prior: must be true or false"};
      p.sim_x0_from_prior = it->get<bool>();
    }
    if (p.sim_x0_from_prior) {
      auto drawn = p.instance->with_x0_from_prior();
      if (!drawn) {
        const std::string who = p.instance->name() == "model"
                                    ? "the model's world simulates its own initial state and the "
                                      "filter starts from a channel's first sample, so it "
                                    : "scenario '" + p.instance->name() + "' ";
        return Error{path + ": sim.x0_from_prior: " + who +
                     "cannot draw its initial state from the filter's prior"};
      }
      p.instance = std::move(drawn);
    }
  }
  return p;
}

}  // namespace

Expected<Preset> parse_preset(const std::string& text, const std::string& path) {
  auto doc = parse_ordered_json_document(text, path);
  if (!doc) return doc.err();
  return preset_from_json(*doc, path);
}

Expected<Preset> load_preset(const std::string& path) {
  auto doc = read_ordered_json_document(path, "preset");
  if (!doc) return doc.err();
  return preset_from_json(*doc, path);
}

std::string preset_to_json(const Preset& preset) {
  nlohmann::ordered_json j;
  j["format"] = kPresetFormat;
  j["version"] = kPresetVersion;
  j["scenario"] = preset.scenario;
  j["title"] = preset.title;
  j["description"] = preset.description;
  if (preset.data_path) j["data"] = path_for_file(*preset.data_path, preset.path);
  const std::shared_ptr<const Scenario>& scenario = preset.instance;
  const bool own_table = !preset.model.is_null();
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  if (scenario) {
    for (const auto& spec : scenario->params().specs()) {
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
      auto m = preset.meta.find(spec.key);
      const ParamMeta meta =
          m == preset.meta.end() ? ParamMeta{spec.tunable, spec.scale_group} : m->second;
      e["tunable"] = meta.tunable;
      if (!meta.scale_group.empty()) e["scale_group"] = meta.scale_group;
      if (own_table) {
        if (!spec.group.empty()) e["group"] = spec.group;
        if (!spec.description.empty()) e["description"] = spec.description;
      }
      params[spec.key] = e;
    }
  }
  j["parameters"] = params;
  if (!preset.mapping.blank()) j["mapping"] = mapping_to_json(preset.mapping);
  if (!preset.model.is_null()) j["model"] = preset.model;
  if (preset.sim_x0_from_prior) j["sim"] = {{"x0_from_prior", true}};
  if (!preset.default_objective.empty()) j["default_objective"] = preset.default_objective;
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

std::string preset_name_hint(const std::string& name) {
  if (name.find('/') != std::string::npos || fs::path(name).extension() == ".json") return "";
  std::error_code ec;
  const fs::path models = fs::path(preset_dir()) / "models";
  if (fs::is_regular_file(models / (name + ".json"), ec)) {
    return " (did you mean " + quote_token("models/" + name) + "?)";
  }
  std::vector<std::string> names;
  for (const auto& dir : {fs::path(preset_dir()), models}) {
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      if (e.path().extension() != ".json") continue;
      names.push_back((dir == models ? "models/" : "") + e.path().stem().string());
    }
  }
  return did_you_mean(name, names);
}

std::string retired_model_path(std::string_view scenario) {
  const RetiredScenario* r = find_retired(scenario);
  if (!r) return {};
  return (fs::path(preset_dir()) / std::string(r->preset)).string();
}

}  // namespace kfw
