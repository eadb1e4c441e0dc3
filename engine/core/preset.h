// Presets: one JSON file per scenario with every parameter's value, range and unit.
//   {"format": "kfw-preset", "version": 1, "scenario": "helicopter", "title": ..., "description":
//   ...,
//    "data": "optional/path.csv (relative to this file)", "parameters": {"Q": {"value": 67.2,
//    "min": 1e-6, "max": 1e6, "unit": "(deg/s)²", "scale": "log"}, ...}}
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>

#include "core/expected.h"
#include "core/param_spec.h"

namespace kfw {

inline constexpr const char* kPresetFormat = "kfw-preset";
inline constexpr int kPresetVersion = 1;

struct Preset {
  std::string path;  // where it was read from (empty when built in memory)
  std::string scenario;
  std::string title;
  std::string description;
  std::optional<std::string> data_path;  // absolute or relative to the current directory
  ParamValues values;                    // every key of the scenario's table
  // Slider ranges narrowed by the preset, within the table's hard limits.
  std::map<std::string, std::pair<double, double>, std::less<>> ranges;
};

// Reads and validates a preset. Errors name the file and the line/column (JSON syntax) or the key.
Expected<Preset> load_preset(const std::string& path);
Expected<Preset> parse_preset(const std::string& text, const std::string& path);
// The default preset of a scenario: every value from its table.
Expected<Preset> default_preset(const std::string& scenario);
// Serialises with every parameter's value, range, unit and scale.
std::string preset_to_json(const Preset& preset);
Status save_preset(const std::string& path, const Preset& preset);

// The directory the project's presets live in (KFW_PRESETS env var, else the source tree).
std::string preset_dir();
// Resolves "helicopter" or "helicopter.json" to presets/helicopter.json when not a readable path.
std::string resolve_preset_path(const std::string& name_or_path);

}  // namespace kfw
