// Random streams (core/random.h; presets/models/README.md, "Random numbers"), all seeded from
// sim.seed, one per noise source:
//   noise.phase1..3  one uniform each: the sways' phases 2π u
//   noise.theta0     one normal: θ(0) = √P0_theta n (x0_from_prior only)
//   x0               one normal: b(0) = √P0_bias n (x0_from_prior only; else b(0) = bias0)
//   channel.gyro     one normal per sample: the gyro's white noise
//   channel.angle    one normal per sample (a dropped sample draws too): the angle sensor's noise
//   dropout.angle    one uniform per sample: u < angle_dropout drops the angle sample
//   process          one normal per step k = 1..n−1: the bias walk b_k = b_{k−1} + walk √Ts n
#include "oracles/helicopter/helicopter_sim.h"

#include <cmath>
#include <numbers>

#include "core/random.h"

namespace kfw::helicopter {

Dataset simulate(const SimParams& p) {
  const auto n = static_cast<std::size_t>(std::floor(p.duration_s / p.Ts_s)) + 1;
  Dataset d;
  d.source = "simulated helicopter, seed " + std::to_string(p.seed);
  for (const char* name : {"t", "gyro", "angle", "truth", "bias_truth"})
    d.add(name, n);
  auto& t = d.columns[0];
  auto& gyro = d.columns[1];
  auto& angle = d.columns[2];
  auto& truth = d.columns[3];
  auto& bias = d.columns[4];
  // Hover attitude: three incommensurate sways, phases from the seed.
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  const double f[3] = {0.05, 0.17, 0.61};
  const double a[3] = {0.6, 0.3, 0.1};
  double phase[3];
  const char* const phase_streams[3] = {"noise.phase1", "noise.phase2", "noise.phase3"};
  for (int i = 0; i < 3; ++i)
    phase[i] = kTwoPi * RandomStream(p.seed, phase_streams[i]).uniform();
  double b = p.bias0;
  double offset = 0.0;  // θ(0) drawn from the prior: the sways shifted to start there
  if (p.x0_from_prior) {
    const double theta0 = std::sqrt(p.P0_theta) * RandomStream(p.seed, "noise.theta0").normal();
    b = std::sqrt(p.P0_bias) * RandomStream(p.seed, "x0").normal();
    double sway0 = 0.0;
    for (int i = 0; i < 3; ++i)
      sway0 += p.amplitude_deg * a[i] * std::sin(phase[i]);
    offset = theta0 - sway0;
  }
  RandomStream gyro_noise(p.seed, "channel.gyro"), angle_noise(p.seed, "channel.angle");
  RandomStream dropout(p.seed, "dropout.angle"), process(p.seed, "process");
  const double walk = p.bias_walk * std::sqrt(p.Ts_s);
  for (std::size_t k = 0; k < n; ++k) {
    const double tk = static_cast<double>(k) * p.Ts_s;
    double theta = offset, omega = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double w = kTwoPi * f[i];
      theta += p.amplitude_deg * a[i] * std::sin(w * tk + phase[i]);
      omega += p.amplitude_deg * a[i] * w * std::cos(w * tk + phase[i]);
    }
    if (k > 0) b += walk * process.normal();
    t[k] = tk;
    truth[k] = theta;
    bias[k] = b;
    gyro[k] = omega + b + p.sigma_gyro * gyro_noise.normal();
    const double noisy = theta + p.sigma_angle * angle_noise.normal();
    angle[k] = dropout.uniform() < p.angle_dropout ? kNoSample : noisy;
  }
  return d;
}

}  // namespace kfw::helicopter
