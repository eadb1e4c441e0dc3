#include "model/imm/imm_metrics.h"

#include <cmath>
#include <limits>

#include "model/imm/imm_spec.h"

namespace kfw::model {

std::vector<MetricSpec> imm_metric_specs(const ModelSpec& spec) {
  if (!spec.modes) return {};
  std::vector<MetricSpec> out{{"imm.modes", "IMM modes", "",
                               "Modes of the IMM (the product of a grid's axes, or the list's)",
                               MetricGroup::kScenario, Direction::kNone}};
  for (const GridAxisSpec& a : spec.modes->grid) {
    out.push_back({"imm." + a.param + ".final", "IMM estimate of " + a.label + " at the end",
                   a.unit, "The μ-weighted grid value Σ μ^j " + a.param + "^j at the last row",
                   MetricGroup::kScenario, Direction::kNone});
    if (a.truth.empty()) continue;
    out.push_back({"rmse." + a.param, "RMSE of the IMM's " + a.label, a.unit,
                   "RMS over the rows of the μ-weighted estimate of " + a.param +
                       " minus its truth column '" + a.truth + "'",
                   MetricGroup::kAccuracy, Direction::kLower});
  }
  return out;
}

void add_imm_metrics(const ModelSpec& spec, const Dataset& d, ModelResult& r) {
  if (!spec.modes || !r.imm) return;
  ImmSeries& s = *r.imm;
  r.metrics["imm.modes"] = static_cast<double>(s.modes());
  for (std::size_t a = 0; a < s.axes.size(); ++a) {
    ImmSeries::Axis& axis = s.axes[a];
    double last = std::numeric_limits<double>::quiet_NaN();
    for (double v : axis.estimate) {
      if (std::isfinite(v)) last = v;
    }
    r.metrics["imm." + axis.param + ".final"] = last;
    const std::string& col = spec.modes->grid[a].truth;
    if (col.empty()) continue;
    const std::string key = "rmse." + axis.param;
    if (!d.has(col)) {
      r.undefined.emplace(key, "the truth column '" + col + "' is not in the data");
      continue;
    }
    axis.truth = d.col(col);
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t k = 0; k < axis.estimate.size() && k < axis.truth.size(); ++k) {
      const double e = axis.estimate[k] - axis.truth[k];
      if (!std::isfinite(e)) continue;
      sum += e * e;
      ++n;
    }
    if (n == 0) {
      r.undefined.emplace(key, "no row has both an estimate and a truth value");
    } else {
      r.metrics[key] = std::sqrt(sum / static_cast<double>(n));
    }
  }
}

}  // namespace kfw::model
