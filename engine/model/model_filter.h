// Runs a model's filter over a dataset: kf (linear, Joseph form), ekf (exact symbolic Jacobians),
// ukf (scaled sigma points). Per row k: no prediction at the first row; else dt = t[k] − t[k−1]
// and x_{k|k−1} from x_{k−1|k−1} with the inputs of row k−1 (a missing input holds its last
// value, 0 before the first); then every channel whose clock allows (k % every == 0) and whose
// values are all present updates, in the order of the channel names.
#pragma once

#include <memory>

#include "core/scenario.h"
#include "model/model_result.h"
#include "model/model_spec.h"

namespace kfw::model {

// kSteady (issue 30): the fixed DARE gain of a linear time-invariant model with one channel (the
// m-step gain for a channel with `every` = m), the covariance carried in Joseph form for that gain.
enum class FilterKind { kKf, kEkf, kUkf, kSteady };

struct FilterOptions {
  FilterKind kind = FilterKind::kKf;
  // Scaled unscented transform (Julier 2002; Wan & van der Merwe 2000): λ = α²(n + κ) − n.
  double alpha = 1.0, beta = 2.0, kappa = 0.0;
};

// Parses "kf", "ekf", "ukf", "steady".
Expected<FilterKind> filter_kind(const std::string& name);

// The run. Bad parameters or data (missing columns, P0/Q/R not PSD at parameter values) come
// back as an Error (exit 2); a breakdown (Q or R losing definiteness where they depend on the
// state or time, a state that stops being finite, P losing definiteness in the UKF) as
// failure("step K (t = T s): ...") (exit 1).
Expected<std::shared_ptr<ModelResult>> run_model_filter(const ModelSpec& spec, const Dataset& d,
                                                        const ParamValues& values,
                                                        const FilterOptions& options,
                                                        const RunControl& control = {});

}  // namespace kfw::model
