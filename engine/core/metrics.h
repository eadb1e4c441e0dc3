// Metrics declared once: a MetricSpec per metric (key, label, unit, description, group, direction,
// optional good/bad bounds). The metrics table, Tune, Sweep, the CLI and the README read these.
//
// The vocabulary shared by every scenario and model:
//   rmse                 the primary estimate against truth (the scenario names its primary state)
//   rmse.<state>         every state that has truth
//   nis_mean             NIS / dof, averaged over all updates of all channels (target 1)
//   nis_mean.<channel>   raw NIS mean of one channel (target: that channel's dof)
//   nis_in_bounds        fraction of NIS inside the two-sided 95 % χ² bounds (target 0.95)
//   nees_mean            NEES / (states with truth), averaged (target 1)
//   nees_in_bounds       fraction of NEES inside its 95 % bounds (target 0.95)
//   nll                  mean innovation negative log-likelihood
//   whiteness_p          Ljung–Box p of the worst channel; whiteness_p.<channel> per channel
//                        (a vector channel: its worst component, whiteness_p.<channel>.<role>)
// Scenario-specific metrics keep their own names and are declared by the scenario.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace kfw {

// Summary numbers of a run: a flat, ordered map of finite values.
using Metrics = std::map<std::string, double>;
// Metric key -> why it is undefined for a run ("no truth column"). Never NaN, never null.
using UndefinedMetrics = std::map<std::string, std::string>;

enum class MetricGroup { kAccuracy, kConsistency, kGains, kScenario };
// kNone: informational (a gain, a count, an operating point): nothing to rank by.
enum class Direction { kLower, kHigher, kTarget, kNone };

struct MetricSpec {
  std::string key;          // "rmse", "nis_mean.<channel>" (a pattern), "tracking_rmse"
  std::string label;        // "RMSE of the primary estimate"
  std::string unit;         // "deg"; empty when dimensionless
  std::string description;  // one line
  MetricGroup group = MetricGroup::kScenario;
  Direction direction = Direction::kLower;
  double target = 0.0;  // for kTarget
  // Optional good range: a value inside [good_lo, good_hi] is "good", outside "bad".
  std::optional<double> good_lo, good_hi;
};

const char* group_name(MetricGroup g);    // "accuracy", ...
const char* direction_name(Direction d);  // "lower", "higher", "target"
// The shared vocabulary (patterns end in ".<state>" / ".<channel>").
const std::vector<MetricSpec>& shared_metric_specs();

// What a score means for ranking: smaller is better. lower: v; higher: −v; target: |v − target|;
// none: 0 (no value is better than another).
double badness(const MetricSpec& spec, double value);
// True when `a` is better than `b` by the spec's direction.
bool better(const MetricSpec& spec, double a, double b);
// "good", "bad" or "" (no bounds declared).
std::string judge(const MetricSpec& spec, double value);

// Tune objectives that combine metrics (ranked by experiment/tuning.h), declared once for the
// CLI, the Tune dialog and a preset's default_objective.
inline constexpr const char* kRmseNis = "rmse+nis";    // RMSE, a scale group's scale by NIS
inline constexpr const char* kRmseAnis = "rmse+anis";  // RMSE + |ln(NIS mean / dof)|
struct CombinedObjective {
  std::string_view name;         // "rmse+nis"
  std::string_view label;        // "RMSE, noise scale by NIS consistency"
  std::string_view description;  // one line
};
const std::vector<CombinedObjective>& combined_objectives();
bool is_combined_objective(std::string_view name);

// The identifier form of a display name: "range 1" -> "range_1" (letters, digits, '_').
std::string metric_identifier(std::string_view name);

}  // namespace kfw
