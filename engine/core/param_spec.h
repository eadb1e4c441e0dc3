// Parameters are data: one table per scenario, consumed by the GUI (sliders), presets (JSON) and
// the command line (--set key=value).
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"

namespace kfw {

enum class Scale {
  kLinear,   // slider linear in the value
  kLog,      // slider linear in log10(value); for variances spanning decades
  kInteger,  // whole numbers
  kChoice,   // one of `choices`, stored as its index; --set accepts the label
  kToggle,   // 0 or 1
};

struct ParamSpec {
  std::string key;    // "Q", "sim.sigma_gyro"
  std::string label;  // "Q = N_ω (gyro noise variance)"
  std::string unit;   // "(deg/s)²"; empty when dimensionless
  double min = 0.0;
  double max = 1.0;
  double def = 0.0;
  Scale scale = Scale::kLinear;
  std::string group;  // "Filter", "Simulator", ...: how the GUI groups its sliders
  std::string description;
  int decimals = 3;                  // spin-box precision for linear scales
  std::vector<std::string> choices;  // labels for kChoice
  // Defaults of the preset's per-parameter flags (a preset may override them).
  bool tunable = false;     // offered to the tuner
  std::string scale_group;  // noise variances that scale together
  // Shown only while the choice parameter `shown_with` holds one of the labels `shown_for` (the
  // UKF's α, β, κ under filter = ukf); empty: always. The window hides the row otherwise; every
  // other surface (CLI, tune, sweep, sessions) takes the key whatever the choice.
  std::string shown_with;
  std::vector<std::string> shown_for;
};

// Values by key. Ordered, so that output is stable.
using ParamValues = std::map<std::string, double, std::less<>>;

class ParamTable {
 public:
  ParamTable() = default;
  explicit ParamTable(std::vector<ParamSpec> specs) : specs_(std::move(specs)) {}

  const std::vector<ParamSpec>& specs() const { return specs_; }
  const ParamSpec* find(std::string_view key) const;
  ParamValues defaults() const;

  // Checks one value against its spec: range, integer, choice index. The message names the key.
  Status check(std::string_view key, double value) const;
  // Checks every value and that every key is known.
  Status check(const ParamValues& values) const;
  // Parses "key=value" (value a number, or a choice label) and sets it in `values` when valid.
  Status apply_assignment(std::string_view assignment, ParamValues& values) const;
  // Formats a value for display: the choice label, an integer, or a number.
  std::string format(std::string_view key, double value) const;

 private:
  std::vector<ParamSpec> specs_;
};

// Reads a value that the table guarantees to exist.
double param(const ParamValues& values, std::string_view key);

// Parses a whole string as a finite double; false on trailing junk, empty input, NaN or infinity.
bool parse_double(std::string_view text, double& out);

}  // namespace kfw
