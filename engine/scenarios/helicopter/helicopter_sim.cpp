#include "scenarios/helicopter/helicopter_sim.h"

#include <cmath>
#include <numbers>
#include <random>

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
  std::mt19937_64 rng(p.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  // Hover attitude: three incommensurate sways, phases from the seed.
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  const double f[3] = {0.05, 0.17, 0.61};
  const double a[3] = {0.6, 0.3, 0.1};
  double phase[3];
  for (double& ph : phase)
    ph = kTwoPi * uni(rng);
  double b = p.bias0;
  double offset = 0.0;  // θ(0) drawn from the prior: the sways shifted to start there
  if (p.x0_from_prior) {
    std::mt19937_64 prior_rng(p.seed ^ 0x5DEECE66DULL);  // leaves the noise streams alone
    std::normal_distribution<double> prior(0.0, 1.0);
    const double theta0 = std::sqrt(p.P0_theta) * prior(prior_rng);
    b = std::sqrt(p.P0_bias) * prior(prior_rng);
    double sway0 = 0.0;
    for (int i = 0; i < 3; ++i)
      sway0 += p.amplitude_deg * a[i] * std::sin(phase[i]);
    offset = theta0 - sway0;
  }
  const double walk = p.bias_walk * std::sqrt(p.Ts_s);
  for (std::size_t k = 0; k < n; ++k) {
    const double tk = static_cast<double>(k) * p.Ts_s;
    double theta = offset, omega = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double w = kTwoPi * f[i];
      theta += p.amplitude_deg * a[i] * std::sin(w * tk + phase[i]);
      omega += p.amplitude_deg * a[i] * w * std::cos(w * tk + phase[i]);
    }
    t[k] = tk;
    truth[k] = theta;
    bias[k] = b;
    gyro[k] = omega + b + p.sigma_gyro * unit(rng);
    const double noisy = theta + p.sigma_angle * unit(rng);
    angle[k] = uni(rng) < p.angle_dropout ? kNoSample : noisy;
    b += walk * unit(rng);
  }
  return d;
}

}  // namespace kfw::helicopter
