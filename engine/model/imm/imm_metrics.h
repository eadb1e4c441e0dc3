// The metrics of a model with modes (presets/models/README.md, "Modes"): imm.modes, and per grid
// axis its last estimate and, with a truth column, its RMSE.
#pragma once

#include <vector>

#include "core/metrics.h"
#include "core/scenario.h"
#include "model/model_result.h"
#include "model/model_spec.h"

namespace kfw::model {

std::vector<MetricSpec> imm_metric_specs(const ModelSpec& spec);
// Binds each grid axis's truth column of `d` (when there) and adds the metrics to r.metrics.
void add_imm_metrics(const ModelSpec& spec, const Dataset& d, ModelResult& r);

}  // namespace kfw::model
