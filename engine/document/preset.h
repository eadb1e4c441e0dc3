// Presets: one JSON file with a scenario (or a model) and every parameter's value, range and unit.
// Format version 2 is specified in presets/README.md (a schema table: key, type, meaning,
// default); version 1 files still load. A key that is not in the table is an error naming it.
#pragma once

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/expected.h"
#include "core/param_spec.h"
#include "data/mapping.h"

namespace kfw {

class Scenario;

inline constexpr const char* kPresetFormat = "kfw-preset";
inline constexpr int kPresetVersion = 2;  // written; 1 and 2 are read

// Per-parameter flags of version 2.
struct ParamMeta {
  bool tunable = false;     // offered to the tuner (Q, R, γ; not m, window, Ts)
  std::string scale_group;  // noise variances that scale together (the tuner's invariance check)
  bool operator==(const ParamMeta&) const = default;
};

struct Preset {
  std::string path;              // where it was read from (empty when built in memory)
  int version = kPresetVersion;  // the version the file declared
  std::string scenario;
  std::string title;
  std::string description;
  std::optional<std::string> data_path;  // absolute or relative to the current directory
  ParamValues values;                    // every key of the scenario's table
  // Slider ranges narrowed by the preset, within the table's hard limits.
  std::map<std::string, std::pair<double, double>, std::less<>> ranges;
  std::map<std::string, ParamMeta, std::less<>> meta;  // every key of the table
  Mapping mapping;       // role -> column, unit, scale/offset (import fills it)
  nlohmann::json model;  // the user-model block ("scenario": "model"); null otherwise
  nlohmann::ordered_json parameters_block;  // a model preset's own parameters, in file order
  // The simulator draws x0 from the filter's prior (the instance is swapped).
  bool sim_x0_from_prior = false;
  // The tune objective when none is asked for (a metric key or a combined objective such as
  // rmse+nis); empty: the tuner's rule (experiment/tuning.h, default_objective).
  std::string default_objective;
  // The scenario this preset runs (built-in, or built from the model block).
  std::shared_ptr<const Scenario> instance;
  // A file that named a retired built-in (core/retired.h) loads as the shipped model file: the
  // name it named, and its parameter keys the model file lacks (dropped).
  std::string retired_from;
  std::vector<std::string> dropped_keys;
  // What loading changed that the user should know (one line each): the GUI shows them, the CLI
  // prints them on stderr. Empty for a current file.
  std::vector<std::string> notices;
};

// Reads and validates a preset. Errors name the file and the line/column (JSON syntax) or the key.
Expected<Preset> load_preset(const std::string& path);
Expected<Preset> parse_preset(const std::string& text, const std::string& path);
// Serialises as version 2 with every parameter's value, range, unit, scale and flags.
std::string preset_to_json(const Preset& preset);
Status save_preset(const std::string& path, const Preset& preset);

// The directory the project's presets live in (KFW_PRESETS env var, else the source tree).
std::string preset_dir();
// Resolves "helicopter" or "helicopter.json" to presets/helicopter.json when not a readable path.
std::string resolve_preset_path(const std::string& name_or_path);
// For a preset name that names no shipped preset: " (did you mean 'models/cv1d'?)" when the name
// is a model file of preset_dir()/models/, else the nearest shipped name's hint; "" for a path.
std::string preset_name_hint(const std::string& name);
// The shipped model file that replaces a retired built-in (core/retired.h), in preset_dir().
std::string retired_model_path(std::string_view scenario);

}  // namespace kfw
