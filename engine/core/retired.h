// The built-in scenarios that shipped model files replace (issues 27, 28 and 30). A preset or a
// session that names one loads as the model file of that name in preset_dir() (document/preset.h),
// with its values overlaid and one notice; `kfw-cli upgrade` rewrites it in the current form. A
// retired built-in stays compiled (make_scenario() builds it for tests and bench) but is listed
// nowhere a user sees scenarios (ScenarioRegistry::listed_names()). One line per retired scenario.
#pragma once

#include <string_view>

namespace kfw {

struct RetiredScenario {
  std::string_view scenario;  // the built-in's name, as presets and sessions wrote it
  std::string_view preset;    // the shipped model file that replaces it, in preset_dir()
};

inline constexpr RetiredScenario kRetiredScenarios[] = {
    {"helicopter", "helicopter.json"},
    {"underwater", "underwater.json"},
    {"radome", "radome.json"},
    {"ballbeam", "ballbeam.json"},
};

// The entry of a retired scenario, or nullptr.
inline const RetiredScenario* find_retired(std::string_view scenario) {
  for (const auto& r : kRetiredScenarios) {
    if (r.scenario == scenario) return &r;
  }
  return nullptr;
}

}  // namespace kfw
