// The metrics of a model's gates (model_gates.cpp): updates each gated channel rejected
// (gated.NAME) and, for channels that name the column marking known outliers (a simulation's
// injected offsets, "outlier_column"), how many of them the gate caught — seed 004, Table 14.
#pragma once

#include <vector>

#include "core/metrics.h"
#include "core/scenario.h"
#include "model/model_spec.h"

namespace kfw::model {

struct ModelResult;

std::vector<MetricSpec> gate_metric_specs(const ModelSpec& spec);
// gated.NAME, and outliers_injected / outliers_detected / outliers_false_alarm (undefined, with
// the reason, when no channel's outlier column is in the data).
void add_gate_metrics(const ModelSpec& spec, const ModelResult& r, Metrics& m,
                      UndefinedMetrics& undefined);

}  // namespace kfw::model
