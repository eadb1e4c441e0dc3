// The built-in scenarios that shipped model files replace (issues 27, 28 and 30). A preset or a
// session that names one loads as the model file of that name in preset_dir() (document/preset.h),
// with its values overlaid and one notice; `kfw-cli upgrade` rewrites it in the current form. The
// built-ins themselves are gone (issue 30); their independent implementations are test oracles in
// tests/oracles/. One line per retired scenario.
#pragma once

#include <array>
#include <string_view>

namespace kfw {

struct RetiredScenario {
  std::string_view scenario;  // the built-in's name, as presets and sessions wrote it
  std::string_view preset;    // the shipped model file that replaces it, in preset_dir()
  std::array<std::string_view, 2> dropped = {};  // the built-in's keys the file lacks

  bool is_dropped(std::string_view key) const {
    for (auto d : dropped) {
      if (!d.empty() && d == key) return true;
    }
    return false;
  }
};

inline constexpr RetiredScenario kRetiredScenarios[] = {
    {"helicopter", "helicopter.json", {"window"}},
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
