// The world block of a model file (version 2): what generates the data in simulation, apart
// from the filter. It is a model block of its own (states, inputs, expressions, x0, P0, process,
// and channels that act as sensors, without "version"), parsed with the simulator's parameters
// sim.X as symbols X; its sensors' roles and inputs are the columns the filter reads, its truth
// map writes the filter's truth columns.
#pragma once

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "core/expected.h"
#include "core/param_spec.h"
#include "model/model_spec.h"

namespace kfw::model {

// Parses model["world"] for the filter `filter` (parsed but for its world): errors name the key
// under model.world, and a column the filter reads that the world does not write.
Expected<std::shared_ptr<const ModelSpec>> parse_world(const nlohmann::json& model,
                                                       const ParamTable& params,
                                                       const std::string& path,
                                                       const ModelSpec& filter);

}  // namespace kfw::model
