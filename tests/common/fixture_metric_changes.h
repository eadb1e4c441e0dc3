// The differences between a seed preset's `kfw-cli metrics` listing today and the one saved in
// tests/fixtures/metrics/ that CHANGES.md lists (issue 27: presets/helicopter.json and
// broad_imu.json became model files; the table under "... are model files"), and nothing else.
// tests/engine/format_fixtures_test.cpp and tests/cli/format_fixtures_cli_test.cpp read it.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace kfw::testing {

struct MetricChange {
  std::string key;
  bool added;  // true: new in the listing; false: gone from it
};

inline const std::vector<MetricChange>& fixture_metric_changes(const std::string& preset) {
  static const std::vector<MetricChange> helicopter_model = {
      {"rmse_sensor", false},      {"k1_final", false},    {"k1_steady", false},
      {"k1_closed_form", false},   {"beta", false},        {"K.theta.angle", true},
      {"K.bias.angle", true},      {"derived.beta", true}, {"derived.k1", true},
      {"derived.p11_over_R", true}};
  static const std::vector<MetricChange> none;
  return preset == "helicopter" || preset == "broad_imu" ? helicopter_model : none;
}

// `keys` without those the changes list as `added` (true) or gone (false), in their order.
inline std::vector<std::string> without_changes(const std::vector<std::string>& keys,
                                                const std::vector<MetricChange>& changes,
                                                bool added) {
  std::vector<std::string> kept;
  for (const auto& k : keys) {
    const bool listed = std::any_of(changes.begin(), changes.end(), [&](const MetricChange& c) {
      return c.key == k && c.added == added;
    });
    if (!listed) kept.push_back(k);
  }
  return kept;
}

// Checks a listing against the saved one: every change happened, the rest is in saved order.
// Returns "" when it holds, else what differs.
inline std::string compare_with_changes(const std::vector<std::string>& listed,
                                        const std::vector<std::string>& saved,
                                        const std::vector<MetricChange>& changes) {
  std::string why;
  for (const auto& c : changes) {
    const bool now = std::find(listed.begin(), listed.end(), c.key) != listed.end();
    const bool then = std::find(saved.begin(), saved.end(), c.key) != saved.end();
    if (now != c.added || then == c.added) why += " " + c.key;
  }
  if (!why.empty()) return "changes not as listed:" + why;
  if (without_changes(listed, changes, true) != without_changes(saved, changes, false)) {
    return "keys other than the listed changes differ";
  }
  return {};
}

}  // namespace kfw::testing
