// "Bring your own model": a Scenario built from a preset whose "scenario" is "model". The preset's
// "parameters" block becomes the parameter table (sliders, --set keys, symbols of the
// expressions) and its "model" block the model (presets/models/README.md). The table gains
// `filter` (kf / ekf / ukf), `ukf.alpha`, `ukf.beta`, `ukf.kappa`, `sim.seed`, `sim.duration` and
// `sim.dt` when the preset does not declare them.
#pragma once

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "core/scenario.h"

namespace kfw {

// Builds a Scenario from a whole preset JSON whose "scenario" is "model": the preset's
// "parameters" block (full specs: value, min, max, unit, scale, label, optional group) becomes the
// scenario's ParamTable, and its "model" block the model. `path` names the file in messages.
// Errors (exit 2) read "PATH: KEY: what", with the position in an expression where there is one.
Expected<std::unique_ptr<Scenario>> make_model_scenario(const nlohmann::json& preset,
                                                        const std::string& path);

// The parameter table of a "parameters" block in full form (each entry an object with value,
// min, max, and optionally unit, scale, label, group, description, decimals, choices).
Expected<ParamTable> parse_param_table(const nlohmann::json& params, const std::string& path);

}  // namespace kfw
