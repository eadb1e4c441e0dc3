// Every model simulates itself (or its world): the truth from x0 ~ N(x0, P0) through its own
// process with noise drawn from Q on a grid of sim.dt over sim.duration, and each channel's
// measurement z = h(x) + v, v ~ N(0, R), on the grid's rows its `every` allows or, in a world,
// on its clock's ticks (the state moved on from the last grid step by the mean process), with
// its dropouts and outliers; a world's named noise sources as symbols. Random numbers by
// core/random.h from sim.seed, one stream per noise source (x0, process, channel.NAME,
// noise.NAME, clock.NAME, dropout.NAME, outliers.GROUP).
#pragma once

#include <string>

#include "core/dataset.h"
#include "core/param_spec.h"
#include "core/types.h"
#include "model/model_spec.h"

namespace kfw::model {

// Columns: t, the inputs (their `sim` expressions of t), every channel role (NaN where the channel
// does not sample; angle components wrapped), the truth columns of the mapped states and of a
// world's sub-expressions, the outlier columns of a world's sensors. A breakdown
// (non-finite truth, Q or R not PSD where evaluated) comes back as failure("step K ...").
Expected<Dataset> simulate_model(const ModelSpec& spec, const ParamValues& values,
                                 const std::string& name);

// Sample noise with covariance M: a square root L (L Lᵀ = M) of a PSD matrix, singular allowed.
// False when M is not PSD to rounding.
bool psd_sqrt(const MatX& M, MatX& L);

}  // namespace kfw::model
