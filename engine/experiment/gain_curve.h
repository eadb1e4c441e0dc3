// Steady-state gain entries of any scenario versus one of its parameters: the generalisation of
// the k1(β) curve of seed 000 (Fig. 3) and the α-β curve of seed 003. Each point is one call of
// Scenario::gain() with the parameter moved and every other value kept.
#pragma once

#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/scenario.h"

namespace kfw {

struct GainCurve {
  std::string key;                   // the parameter moved
  bool log = false;                  // spaced logarithmically (a log-scale parameter)
  std::vector<double> x;             // the parameter's values, ascending
  std::vector<std::string> entries;  // gain keys ("K.x.pos", ...), as gain() names them
  // Each entry's declared unit ("" when dimensionless); empty when the scenario declares none.
  std::vector<std::string> units;
  std::vector<std::vector<double>> values;  // [entry][point]; NaN where there is no steady state
  // With an x metric (gain --curve KEY --x DERIVED): gain()'s value of that metric at each point
  // (NaN where gain() fails), e.g. seed 000's β against which k1 is drawn.
  std::string x_key;
  std::vector<double> x_metric;
  double at_x = 0.0;       // the live operating point: the current value ...
  std::vector<double> at;  // ... and each entry's gain there
  Metrics steady;          // everything gain() reports at the current value
};

// The gain entries whose key starts with `prefix`, at `points` values of `key` over its declared
// range (log-spaced for a log-scale parameter) plus the current value, and with `x_key` that
// metric of gain() at each point (refused, naming the metrics gain() reports besides the gains,
// when gain() has none of that name). Fails (with gain()'s
// message) when the current values have no steady state, or when `key` is not a continuous
// parameter of the scenario. A point without a steady state is NaN, not an error.
Expected<GainCurve> gain_curve(const Scenario& s, const ParamValues& values, const std::string& key,
                               std::size_t points = 100, const Dataset* data = nullptr,
                               const std::string& prefix = "K.", const std::string& x_key = "");

// The named quantities of gain() — gain entries ("K.theta.angle") or a model file's derived
// scalars ("derived.k1") — at `points` values of `key` over [lo, hi] (lo = hi = 0: its declared
// range), with `x_key` as gain_curve(): the data of a model file's gain_curve plot block. Each
// entry must be reported by gain() at the current values (else an Error naming it).
Expected<GainCurve> gain_curve_of(const Scenario& s, const ParamValues& values,
                                  const std::string& key, const std::vector<std::string>& entries,
                                  const std::string& x_key, std::size_t points = 100,
                                  const Dataset* data = nullptr, double lo = 0.0, double hi = 0.0);

// The parameters a gain curve can follow: continuous (linear or log), not a simulator setting.
std::vector<std::string> gain_curve_parameters(const Scenario& s);

// The parameter a gain curve shows first: the first of gain_curve_parameters() (log-scale ones —
// noise intensities — before linear ones) that moves the steady-state gain (an initial variance
// P0 does not); empty when none does or there is no steady state.
std::string default_gain_curve_parameter(const Scenario& s, const ParamValues& values,
                                         const Dataset* data = nullptr);

}  // namespace kfw
