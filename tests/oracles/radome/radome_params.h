// Test-only: the seed preset's parameters (presets/radome.json, the keys of the retired built-in
// scenario's table) as the oracle's SimParams and FilterParams — moved from
// tests/engine/imm_model_radome_test.cpp (issue 30) so the model file and the oracle read one
// mapping.
#pragma once

#include <cstdint>

#include "core/param_spec.h"
#include "oracles/radome/radome_imm.h"
#include "oracles/radome/radome_sim.h"

namespace kfw::radome {

inline SimParams sim_params(const ParamValues& v) {
  SimParams s;
  s.seed = static_cast<std::uint64_t>(v.at("sim.seed"));
  s.amplitude = v.at("sim.amplitude");
  s.duration_s = v.at("sim.duration");
  s.Ts_s = v.at("sim.Ts");
  s.range0_m = v.at("sim.range0");
  s.az0_deg = v.at("sim.az0");
  s.el0_deg = v.at("sim.el0");
  s.weave_deg = v.at("sim.weave");
  s.weave_period_s = v.at("sim.weave_period");
  s.target_g = v.at("sim.target_g");
  s.var_angle_rad2 = v.at("sim.R");
  s.var_range_m2 = v.at("sim.R_range");
  return s;
}

inline FilterParams filter_params(const ParamValues& v) {
  FilterParams f;
  f.Q = v.at("Q");
  f.tau_s = v.at("tau");
  f.var_angle = v.at("R");
  f.var_range = v.at("R_range");
  f.P0_pos_m2 = v.at("P0_pos");
  f.P0_vel_m2ps2 = v.at("P0_vel");
  f.P0_acc_m2ps4 = v.at("P0_acc");
  f.structure = v.at("imm.structure") >= 0.5 ? Structure::kFull : Structure::kAxisBlocks;
  f.Kp = v.at("Kp");
  f.renewal = static_cast<Renewal>(static_cast<int>(v.at("renewal.mode")));
  f.renewal_start_s = v.at("renewal.start");
  f.grid_min = v.at("grid.min");
  f.grid_max = v.at("grid.max");
  f.n_psi = static_cast<int>(v.at("grid.n_psi"));
  f.n_theta = static_cast<int>(v.at("grid.n_theta"));
  f.stay = v.at("markov.stay");
  return f;
}

}  // namespace kfw::radome
