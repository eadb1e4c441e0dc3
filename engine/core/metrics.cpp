#include "core/metrics.h"

#include <cctype>
#include <cmath>

namespace kfw {

const char* group_name(MetricGroup g) {
  switch (g) {
    case MetricGroup::kAccuracy:
      return "accuracy";
    case MetricGroup::kConsistency:
      return "consistency";
    case MetricGroup::kGains:
      return "gains";
    case MetricGroup::kScenario:
      return "scenario";
  }
  return "scenario";
}

const char* direction_name(Direction d) {
  switch (d) {
    case Direction::kLower:
      return "lower";
    case Direction::kHigher:
      return "higher";
    case Direction::kTarget:
      return "target";
    case Direction::kNone:
      return "none";
  }
  return "lower";
}

const std::vector<MetricSpec>& shared_metric_specs() {
  using G = MetricGroup;
  using D = Direction;
  static const std::vector<MetricSpec> specs = [] {
    std::vector<MetricSpec> v;
    auto add = [&](std::string key, std::string label, std::string unit, std::string desc, G g, D d,
                   double target = 0.0, std::optional<double> lo = {},
                   std::optional<double> hi = {}) {
      v.push_back({std::move(key), std::move(label), std::move(unit), std::move(desc), g, d, target,
                   lo, hi});
    };
    add("rmse", "RMSE (primary estimate)", "",
        "root-mean-square error of the primary estimate against truth, in its own unit",
        G::kAccuracy, D::kLower);
    add("rmse.<state>", "RMSE of <state>", "", "root-mean-square error of <state> against truth",
        G::kAccuracy, D::kLower);
    add("nis_mean", "NIS mean / dof", "",
        "NIS divided by each update's dof, averaged over every update of every channel; 1 when "
        "the filter's innovation covariance is right",
        G::kConsistency, D::kTarget, 1.0);
    add("nis_mean.<channel>", "NIS mean of <channel>", "",
        "mean NIS of one channel (not normalised); its target is the channel's dof",
        G::kConsistency, D::kTarget, 1.0);
    add("nis_in_bounds", "NIS inside 95 % bounds", "",
        "fraction of updates whose NIS lies inside the two-sided 95 % χ² bounds (ideal 0.95)",
        G::kConsistency, D::kTarget, 0.95, 0.9, 1.0);
    add("nees_mean", "NEES mean / dof", "",
        "NEES over the states with truth divided by their number, averaged; 1 when the filter's "
        "covariance is right",
        G::kConsistency, D::kTarget, 1.0);
    add("nees_in_bounds", "NEES inside 95 % bounds", "",
        "fraction of steps whose NEES lies inside the two-sided 95 % χ² bounds (ideal 0.95)",
        G::kConsistency, D::kTarget, 0.95, 0.9, 1.0);
    add("nll", "innovation NLL", "",
        "mean negative log-likelihood of the innovations, ½(d·log 2π + log det S + NIS); needs no "
        "truth",
        G::kConsistency, D::kLower);
    add("whiteness_p", "whiteness p (worst channel)", "",
        "Ljung–Box p-value (20 lags) of the normalised innovations, the worst channel; below "
        "0.01 the innovations are not white",
        G::kConsistency, D::kHigher, 0.0, 0.01, 1.0);
    add("whiteness_p.<channel>", "whiteness p of <channel>", "",
        "Ljung–Box p-value (20 lags) of one channel's normalised innovations; a channel of "
        "several components: the smallest of its components' p, each reported as "
        "whiteness_p.CHANNEL.ROLE",
        G::kConsistency, D::kHigher, 0.0, 0.01, 1.0);
    return v;
  }();
  return specs;
}

const std::vector<CombinedObjective>& combined_objectives() {
  static const std::vector<CombinedObjective> v = {
      {kRmseNis, "RMSE, noise scale by NIS consistency",
       "RMSE, with the common scale of a scale group set by NIS consistency (NIS mean / dof = "
       "1); without a group to set, RMSE · (1 + (ln NIS mean / dof)²)"},
      {kRmseAnis, "RMSE + |ln NIS mean / dof|",
       "RMSE + |ln(NIS mean / dof)|: the RMSE of a filter whose innovations are consistent "
       "(the default with truth and no scale group)"},
  };
  return v;
}

bool is_combined_objective(std::string_view name) {
  for (const auto& c : combined_objectives()) {
    if (c.name == name) return true;
  }
  return false;
}

double badness(const MetricSpec& spec, double value) {
  switch (spec.direction) {
    case Direction::kLower:
      return value;
    case Direction::kHigher:
      return -value;
    case Direction::kTarget:
      return std::abs(value - spec.target);
    case Direction::kNone:
      return 0.0;
  }
  return value;
}

bool better(const MetricSpec& spec, double a, double b) {
  if (!std::isfinite(a) || spec.direction == Direction::kNone) return false;
  if (!std::isfinite(b)) return true;
  return badness(spec, a) < badness(spec, b);
}

std::string judge(const MetricSpec& spec, double value) {
  if (!spec.good_lo && !spec.good_hi) return {};
  if (!std::isfinite(value)) return {};
  const bool ok =
      (!spec.good_lo || value >= *spec.good_lo) && (!spec.good_hi || value <= *spec.good_hi);
  return ok ? "good" : "bad";
}

std::string metric_identifier(std::string_view name) {
  std::string out;
  for (char c : name) {
    const auto u = static_cast<unsigned char>(c);
    out += (std::isalnum(u) || c == '_') ? c : '_';
  }
  return out;
}

}  // namespace kfw
