// What a run of a model scenario's filter is made of, for the C export (engine/codegen/): kept out
// of model_scenario.h, which the widgets include (the model's headers use the name `slots`).
#pragma once

#include <memory>

#include "core/expected.h"
#include "core/param_spec.h"
#include "core/scenario.h"
#include "model/model_filter.h"
#include "model/model_spec.h"

namespace kfw {

// What a run of a model scenario's filter at `values` is made of: the model, every value (checked,
// the modes' parameters added) and the filter's options. For the C export (engine/codegen/). An
// Error when `s` is not a model scenario or a value is out of range.
struct ModelFilterView {
  std::shared_ptr<const model::ModelSpec> spec;
  ParamValues values;
  model::FilterOptions options;
};
Expected<ModelFilterView> model_filter_view(const Scenario& s, const ParamValues& values);

}  // namespace kfw
