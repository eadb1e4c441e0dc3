// A closed loop in a model file (version 2, issue 30; presets/models/README.md, "Closed loops"):
// the controller block that computes the world's inputs every step from the filter's estimate,
// a reference signal of time, its own states and parameters, with saturation. The world's
// limits and events and a sensor's impulses live in model_spec.h (they are world keys).
#pragma once

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/param_spec.h"
#include "model/expression.h"
#include "model/model_spec.h"

namespace kfw::model {

struct ControllerSpec {
  // The controller's own symbols: parameters (sim.X as X where X is free), t, dt, the filter's
  // estimates (its state names) and variances (var_STATE), the world's columns it reads, the
  // reference, its states, its outputs and its sub-expressions.
  Symbols symbols;
  std::vector<int> param_slots;
  std::vector<std::string> param_keys;
  int t_slot = -1, dt_slot = -1;
  std::vector<int> estimate_slots, variance_slots;  // per filter state
  // A world column the controller reads: a sensor's role (its last sample held, 0 before the
  // first) or a world input.
  struct Column {
    std::string name;
    int slot = -1;
  };
  std::vector<Column> columns;
  std::string reference_name;  // empty: no reference
  int reference_slot = -1;
  Expr reference;  // parameters and t
  struct State {
    std::string name;
    int slot = -1;
    Expr x0;    // parameters only
    Expr next;  // the value at the next step: every symbol, the outputs after saturation
  };
  std::vector<State> states;
  struct Output {
    std::string name;
    int slot = -1;
    Expr e, lo, hi;  // lo, hi: parameters only ("-1e308", "1e308" when not given)
    int world_input = -1;
  };
  std::vector<Output> outputs;
  // The choice parameter that closes the loop (`loop.param`) and, per choice index, whether the
  // loop is closed; empty: always closed.
  std::string loop_param;
  std::vector<bool> closed_by_choice;
  // Noise-free responses: {column written, the world's column it copies from the noise-free run}.
  std::vector<std::pair<std::string, std::string>> noise_free;
};

// Parses model.controller against the filter model and its world (both parsed), and adds the
// loop's columns (reference, outputs, noise-free responses) to `m` as symbols of derived series.
Expected<std::shared_ptr<const ControllerSpec>> parse_controller(const nlohmann::json& model,
                                                                 const ParamTable& params,
                                                                 ModelSpec& m);

// Whether the loop closes at these values (`loop.param` at a closed label, or no `loop`).
bool loop_closed(const ControllerSpec& c, const ParamValues& values);

namespace detail {
class Reader;
// A world's model.limits and model.events (states parsed), a sensor's impulses, and a filter
// channel's missing flag.
Status parse_limits(const Reader& p, const nlohmann::json& world, ModelSpec& m);
Status parse_events(const Reader& p, const nlohmann::json& world, ModelSpec& m);
Status parse_impulses(const Reader& p, const nlohmann::json& j, const std::string& key,
                      ChannelSpec& c);
Status parse_missing(const Reader& p, const nlohmann::json& j, const std::string& key,
                     ChannelSpec& c);
}  // namespace detail

}  // namespace kfw::model
