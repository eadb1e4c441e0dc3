// "Bring your own model": a Scenario built from a preset whose "scenario" is "model". The preset's
// "parameters" block becomes the parameter table (sliders, --set keys, symbols of the
// expressions) and its "model" block the model (presets/models/README.md). The table gains
// `filter` (kf / ekf / ukf), `ukf.alpha`, `ukf.beta`, `ukf.kappa`, `sim.seed`, `sim.duration` and
// `sim.dt` when the preset does not declare them.
#pragma once

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/scenario.h"
#include "model/plots/model_plots.h"

namespace kfw {

// What a view needs to lay out a model's plots before the first run: its states and its
// measurement channels with their roles (plain data; the model itself stays in the engine).
struct ModelLayout {
  struct State {
    std::string name, label, unit;
    double turn = 0.0;  // an angle's full turn (2π rad, 360 deg): plots break at its wrap; 0: none
  };
  struct Role {
    std::string name, unit;
    bool angle = false;  // wrapped to (−π, π] or (−180, 180]: a line through it would jump
    double turn = 0.0;   // the angle's full turn; 0 when not an angle
  };
  struct Channel {
    std::string name, label;
    std::vector<Role> roles;
  };
  std::vector<State> states;
  std::vector<Channel> channels;
  bool time_invariant = false;  // linear, F B Q H R of parameters and dt only: a steady state
  bool modes = false;           // an IMM over modes (model.modes): mode probabilities to draw
  struct GridAxis {
    std::string param, label, unit;
  };
  std::vector<GridAxis> grid;               // a grid IMM's axes (model.modes.grid), in order
  std::vector<model::PlotBlockSpec> plots;  // the blocks the file asks for ("plots"), in order
  std::vector<std::string> first_panels;    // model.first_panels: shown first, in this order
  std::vector<std::string> panels;  // every panel's name (model::panel_names), the view's order
};

// Builds a Scenario from a whole preset JSON whose "scenario" is "model": the preset's
// "parameters" block (full specs: value, min, max, unit, scale, label, optional group) becomes the
// scenario's ParamTable, in the block's order, and its "model" block the model. `path` names the
// file in messages. Errors (exit 2) read "PATH: KEY: what", with the position in an expression
// where there is one. (A nlohmann::json converts, its keys sorted.)
Expected<std::unique_ptr<Scenario>> make_model_scenario(const nlohmann::ordered_json& preset,
                                                        const std::string& path);
// Registers "model" as a scenario built from its preset (core/scenario.h); the generated scenario
// list calls it.
void register_scenario_model(ScenarioRegistry& registry);

// The layout of the model a scenario was built from; empty when `s` is not a model scenario.
std::optional<ModelLayout> model_layout_of(const Scenario& s);

// The parameter table of a "parameters" block in full form (each entry an object with value,
// min, max, and optionally unit, scale, label, group, description, decimals, choices), in the
// block's order.
Expected<ParamTable> parse_param_table(const nlohmann::ordered_json& params,
                                       const std::string& path);

}  // namespace kfw
