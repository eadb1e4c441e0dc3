// Every model simulates itself: the truth from x0 ~ N(x0, P0) through its own process with noise
// drawn from Q, and each channel's measurement z = h(x) + v, v ~ N(0, R), on the rows its clock
// allows (`every`). Random numbers by core/random.h from sim.seed, one stream per noise source
// (x0, process, channel.NAME); a time grid of sim.dt over sim.duration.
#pragma once

#include <string>

#include "core/dataset.h"
#include "core/param_spec.h"
#include "core/types.h"
#include "model/model_spec.h"

namespace kfw::model {

// Columns: t, the inputs (their `sim` expressions of t), every channel role (NaN where the channel
// does not sample; angle components wrapped), the truth columns of the mapped states. A breakdown
// (non-finite truth, Q or R not PSD where evaluated) comes back as failure("step K ...").
Expected<Dataset> simulate_model(const ModelSpec& spec, const ParamValues& values,
                                 const std::string& name);

// Sample noise with covariance M: a square root L (L Lᵀ = M) of a PSD matrix, singular allowed.
// False when M is not PSD to rounding.
bool psd_sqrt(const MatX& M, MatX& L);

}  // namespace kfw::model
