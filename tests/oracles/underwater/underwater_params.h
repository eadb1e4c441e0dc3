// Test-only: the seed preset's parameters (presets/underwater.json, the keys of the retired
// built-in scenario's table) as the oracle's SimParams and FilterParams, and the built-in's
// position RMSE — moved from engine/scenarios/underwater/underwater_scenario.cpp (issue 30) so
// the model file is still compared with the simulator and EKF it replaced, under the same names.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>

#include "core/param_spec.h"
#include "oracles/underwater/underwater_ekf.h"
#include "oracles/underwater/underwater_sim.h"

namespace kfw::underwater {

inline SimParams sim_params(const ParamValues& v) {
  SimParams s;
  s.seed = static_cast<std::uint64_t>(param(v, "sim.seed"));
  s.duration_s = param(v, "sim.duration");
  s.synchronous = param(v, "sim.clock") == 0.0;  // choices: synchronous, asynchronous
  s.dt_sync_s = param(v, "sim.dt_sync");
  s.sigma_t_s = param(v, "sim.sigma_t");
  s.command << param(v, "sim.u_cmd"), 0.0, param(v, "sim.w_cmd"), 0.0, 0.0, param(v, "sim.r_cmd");
  s.motion_sigma << param(v, "sim.motion_sigma_u"), 0.0, param(v, "sim.motion_sigma_w"), 0.0, 0.0,
      param(v, "sim.motion_sigma_r");
  s.velocity_sigma << param(v, "sim.sigma_dvl_u"), param(v, "sim.sigma_dvl_v"),
      param(v, "sim.sigma_dvl_w"), 0.0, 0.0, param(v, "sim.sigma_yaw_rate");
  s.attitude_sigma_rad = param(v, "sim.sigma_attitude") * std::numbers::pi / 180.0;  // deg
  s.sigma_range_m = param(v, "sim.sigma_range");
  s.sigma_depth_m = param(v, "sim.sigma_depth");
  s.sigma_corr_m = param(v, "sim.sigma_corr");
  s.t_gap_s = param(v, "sim.t_gap");
  s.outliers = static_cast<int>(param(v, "sim.outliers"));
  s.outlier_m = param(v, "sim.outlier_size");
  s.range_dropout = param(v, "sim.range_dropout");
  return s;
}

inline FilterParams filter_params(const ParamValues& v) {
  FilterParams f;
  f.scheme = static_cast<Scheme>(static_cast<int>(param(v, "scheme")));  // AS, SC, SI
  f.gate = param(v, "gate");
  f.sigma_range_m = param(v, "sigma_range");
  f.sigma_depth_m = param(v, "sigma_depth");
  f.sigma_corr_m = param(v, "sigma_corr");
  f.corr_in_R = param(v, "corr_in_R") != 0.0;
  f.q_pos = param(v, "q_pos");
  f.sigma0_pos_m = param(v, "sigma0_pos");
  return f;
}

// The built-in's `rmse` (seed 004, Table 13): RMS of the distance error |X̂ − X| over every row
// with truth; NaN without any.
inline double position_rmse(const UnderwaterResult& r) {
  double s2 = 0.0;
  std::size_t n = 0;
  for (double e : r.pos_err) {
    if (!std::isfinite(e)) continue;
    s2 += e * e;
    ++n;
  }
  return n ? std::sqrt(s2 / static_cast<double>(n)) : std::nan("");
}

}  // namespace kfw::underwater
