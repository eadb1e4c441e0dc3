// `noise_param` (model format version 2, issue 27): the parameter a channel's or an input's noise
// sets, checked when the model loads, and the links the generic noise command reads
// (Scenario::noise_links, filter/noise_estimate.h). presets/models/README.md, "Noise links".
#pragma once

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "core/expected.h"
#include "core/param_spec.h"
#include "core/scenario.h"
#include "model/model_spec.h"

namespace kfw::model {

// Reads every noise_param of the model block `j` into `m` (its inputs and channels already
// parsed): each names a declared parameter (did you mean) of a linear or log scale, no parameter
// is named twice, and a channel's R_ii depends on its parameter through parameters and dt only.
// A world's sensors and inputs name none (`world`). Errors read "PATH: KEY: what".
Status parse_noise_params(const nlohmann::json& j, ModelSpec& m, const ParamTable& params,
                          bool world);

// The model's links, inputs first, then channels in the order of their names. An input's
// parameter is the variance v of its noise, or √v ("as": "sigma"); a channel's solves
// Σ_i R_ii(param) = Σ_i v_i over its linked roles, the other parameters at their values, dt the
// data's median interval (a root in the parameter's range nearest its value, in log10 on a log
// scale; else the nearest outside the range, which the command clamps; none: exit 1).
std::vector<NoiseLink> noise_links(const std::shared_ptr<const ModelSpec>& spec,
                                   const ParamTable& table);

}  // namespace kfw::model
