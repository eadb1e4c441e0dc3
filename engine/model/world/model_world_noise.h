// What a world block draws besides its process and sensor noise (version 2): the named noise
// sources, the sensor clocks' ticks and the outliers. Each from its own stream of the
// random-number specification (core/random.h), so adding one leaves the others' draws unchanged.
// Internal to the model room (model_sim.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/expected.h"
#include "core/random.h"
#include "model/model_spec.h"

namespace kfw::model::detail {

// The value of an expression of parameters at `vars` (the symbols' values by slot); an Error names
// `key` when it is not finite.
Expected<double> param_value(const Expr& e, const ModelSpec& spec, std::vector<double>& vars,
                             const std::string& key);

class NoiseSources {
 public:
  // Reads each source's sigma, tau, hold, min, max at the parameters in `vars` (errors name the
  // key: a negative sigma or hold, tau ≤ 0, max < min, more than `max_windows` hold windows over
  // the duration) and opens its stream "noise.NAME".
  static Expected<NoiseSources> create(const ModelSpec& world, std::vector<double>& vars,
                                       std::uint64_t seed, double dt, double duration,
                                       std::size_t max_windows);
  // The sim.dt grid's step j (called for j = 0, 1, … in order): white sources draw, random walks
  // and Gauss–Markov sources move on.
  void step(std::size_t j);
  // Held sources at time t: the draw of t's window (windows drawn in order, each once).
  void at_time(double t);
  // Each source's current value into vars[slot].
  void write(double* vars) const;

 private:
  struct Source {
    const NoiseSourceSpec* spec;
    RandomStream stream;
    double sigma = 0, lo = 0, hi = 0, hold = 0, a = 0, b = 0;  // a, b: x ← a x + b n (GM, RW)
    double value = 0;
    std::vector<double> held;  // held: the draws of the windows reached so far
  };
  double draw(Source& s);
  std::vector<Source> sources_;
};

// The ticks of a clock from 0 to `duration` (inclusive, to 1e-9 s): t₀ = offset, then
// tᵢ₊₁ = tᵢ + max(period + jitter·n, period/10), each rounded to the resolution. Errors name the
// key (period ≤ 0, negative jitter, offset, resolution, or more than `max_ticks` ticks).
Expected<std::vector<double>> clock_ticks(const ClockSpec& clock, const ModelSpec& world,
                                          std::vector<double>& vars, std::uint64_t seed,
                                          double duration, std::size_t max_ticks);

// One sample of a sensor: its row and channel.
struct Sample {
  std::size_t row, channel;
};
// One outlier: the sample and the offset added to each of its roles.
struct Outlier {
  Sample sample;
  double offset;
};
// The outliers of one group of sensors, from their samples (in row, then channel order): `count`
// samples drawn without replacement (a partial Fisher–Yates shuffle, index i + ⌊u (n − i)⌋) or
// each sample with probability `rate`; the sign by a second uniform (< ½: −size). Stream
// "outliers.GROUP".
std::vector<Outlier> draw_outliers(std::vector<Sample> samples, bool by_count, double amount,
                                   double size, std::uint64_t seed, const std::string& group);

}  // namespace kfw::model::detail
