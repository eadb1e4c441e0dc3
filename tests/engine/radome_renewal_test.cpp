// Mode-parameter renewal (seed 001, eq. 4) keeping each mode probability with its slope: no shift
// is the identity, a whole grid step moves the mass one index, half a step splits it, the total
// is kept and so is the mean slope while the mass stays inside the grid. Without renewal the
// three readings of eq. 4 are the plain IMM (in grid: under 0.5° over seeds 1–10); with it they
// move the grid differently.
#include "scenarios/radome/radome_renewal.h"

#include <gtest/gtest.h>

#include <cmath>

#include "document/preset.h"
#include "experiment/monte_carlo.h"

namespace kfw::radome {
namespace {

const std::vector<double> kOff = {-0.05, -0.025, 0.0, 0.025, 0.05};
const std::vector<double> kOne = {0.0};

VecX along_psi(std::initializer_list<double> v) {
  VecX mu(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v)
    mu(i++) = x;
  return mu;
}

double mean_slope(const VecX& mu, double centre) {
  double m = 0.0;
  for (Eigen::Index i = 0; i < mu.size(); ++i)
    m += mu(i) * (centre + kOff[static_cast<std::size_t>(i)]);
  return m;
}

TEST(RadomeRenewal, KeepsEachProbabilityWithItsSlope) {
  const VecX mu = along_psi({0.1, 0.2, 0.4, 0.2, 0.1});
  EXPECT_TRUE(remap_probabilities(mu, kOff, kOne, 0.0, 0.0).isApprox(mu, 1e-15));
  // The grid moves up one step: the old slope of index i is the new index i − 1.
  const VecX up = remap_probabilities(mu, kOff, kOne, 0.025, 0.0);
  EXPECT_NEAR(up(0), 0.1 + 0.2, 1e-15);  // the lowest old slope is below the moved grid
  EXPECT_NEAR(up(1), 0.4, 1e-15);
  EXPECT_NEAR(up(2), 0.2, 1e-15);
  EXPECT_NEAR(up(3), 0.1, 1e-15);
  EXPECT_NEAR(up(4), 0.0, 1e-15);
  // Half a step: each interior mass splits between the two neighbours; the mean slope stays.
  const VecX inner = along_psi({0.0, 0.25, 0.5, 0.25, 0.0});
  const VecX half = remap_probabilities(inner, kOff, kOne, 0.0125, 0.0);
  EXPECT_NEAR(half.sum(), 1.0, 1e-15);
  EXPECT_NEAR(half(0), 0.125, 1e-15);
  EXPECT_NEAR(mean_slope(half, 0.0125), mean_slope(inner, 0.0), 1e-15);
}

TEST(RadomeRenewal, TwoAxesMoveIndependently) {
  // n_ψ = 5, n_θ = 5, all mass at (a, b) = (2, 3): a θ move of one step down moves b to 4.
  VecX mu = VecX::Zero(25);
  mu(2 + 5 * 3) = 1.0;
  const VecX moved = remap_probabilities(mu, kOff, kOff, 0.0, -0.025);
  EXPECT_NEAR(moved(2 + 5 * 4), 1.0, 1e-15);
  EXPECT_NEAR(moved.sum(), 1.0, 1e-15);
}

std::vector<long long> seeds_1_10() {
  std::vector<long long> s;
  for (long long i = 1; i <= 10; ++i)
    s.push_back(i);
  return s;
}

TEST(RadomeRenewal, WithoutRenewalEveryReadingIsThePlainImmAndStaysUnderHalfADegree) {
  auto p = load_preset(KFW_SOURCE_DIR "/presets/radome.json");
  ASSERT_TRUE(p.ok()) << p.error();
  ParamValues v = p->values;
  v["sim.amplitude"] = 0.05;
  v["Kp"] = 0.0;
  std::vector<MonteCarloPart> parts;
  for (double mode : {0.0, 1.0, 2.0, 3.0}) {
    v["renewal.mode"] = mode;
    auto part = run_monte_carlo(*p->instance, v, seeds_1_10());
    ASSERT_TRUE(part.ok()) << part.error();
    parts.push_back(std::move(*part));
  }
  int under = 0;
  for (std::size_t i = 0; i < parts[0].runs.size(); ++i) {
    const Metrics& m = parts[0].runs[i].metrics;
    EXPECT_EQ(m, parts[1].runs[i].metrics);
    EXPECT_EQ(m, parts[2].runs[i].metrics);
    EXPECT_EQ(m, parts[3].runs[i].metrics);
    under += m.at("refraction_err_max_deg") < 0.5 ? 1 : 0;
    // No renewal: the grid stays at ±0.05, so no edge is further than 0.1 from the estimate.
    EXPECT_LE(m.at("grid_span_psi"), 0.1 + 1e-12);
    EXPECT_GE(m.at("grid_span_psi"), 0.05 - 1e-12);
  }
  EXPECT_GE(under, 9);
}

TEST(RadomeRenewal, TheReadingsDifferWithRenewal) {
  auto p = load_preset(KFW_SOURCE_DIR "/presets/radome.json");
  ASSERT_TRUE(p.ok()) << p.error();
  ParamValues v = p->values;
  v["sim.amplitude"] = 0.08;
  v["Kp"] = 0.45;
  v["sim.duration"] = 20.0;
  v["renewal.start"] = 0.0;
  std::vector<double> top;
  for (double mode : {0.0, 1.0, 2.0, 3.0}) {
    v["renewal.mode"] = mode;
    auto d = p->instance->simulate(v);
    ASSERT_TRUE(d.ok());
    auto r = p->instance->run(*d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    top.push_back((*r)->metrics.at("grid_psi_max_reached"));
    EXPECT_GT(top.back(), 0.05);  // the grid moved out
  }
  EXPECT_NE(top[0], top[1]);
  EXPECT_NE(top[0], top[2]);
  EXPECT_NE(top[0], top[3]);
}

// The shift as a mode transition moves μ exactly as the slope remapping does.
TEST(RadomeRenewal, ShiftTransitionMovesProbabilitiesLikeTheRemapping) {
  VecX mu(25);
  for (Eigen::Index i = 0; i < 25; ++i)
    mu(i) = 1.0 + static_cast<double>((i * 7) % 5);
  mu /= mu.sum();
  for (const auto& [dp, dt] : {std::pair{0.0, 0.0}, {0.0125, -0.03}, {-0.07, 0.004}}) {
    const MatX T = shift_transition(kOff, kOff, dp, dt);
    EXPECT_TRUE(T.rowwise().sum().isApproxToConstant(1.0, 1e-15));
    EXPECT_TRUE((T.transpose() * mu).isApprox(remap_probabilities(mu, kOff, kOff, dp, dt), 1e-14));
  }
}

// Seed 001, Figs. 7–9, with the reading that carries the mode states with the shift (`mix`, the
// default) and renewal from 2 s: truth B outside the grid is tracked (slope RMSE ≤ 0.0112, the
// refraction error under 0.5° in at least 7 of 10 seeds, every grid edge within 0.1 of the
// estimate), and renewal does not spoil truth A inside the grid (under 0.5° in 9 of 10).
// Truth B was "9 of 10" before the simulators drew from the random-number specification
// (CHANGES.md, issue 27): seeds 1–10 went from 10 to 7 (worst 0.478° → 0.542°, the three misses
// 0.52–0.54°) while over seeds 1–40 the share stayed (33 → 32 of 40; truth A 37 → 39 of 40).
TEST(RadomeRenewal, CarryingTheModeStatesTracksOutsideTheGridAndKeepsTheInGridCase) {
  auto p = load_preset(KFW_SOURCE_DIR "/presets/radome.json");
  ASSERT_TRUE(p.ok()) << p.error();
  ParamValues v = p->values;
  ASSERT_EQ(v.at("renewal.mode"), 3.0);  // mix
  ASSERT_EQ(v.at("renewal.start"), 2.0);
  v["Kp"] = 0.45;
  for (double amplitude : {0.08, 0.05}) {
    v["sim.amplitude"] = amplitude;
    auto part = run_monte_carlo(*p->instance, v, seeds_1_10());
    ASSERT_TRUE(part.ok()) << part.error();
    int under = 0;
    double rmse_psi = 0.0, rmse_theta = 0.0;
    for (const auto& run : part->runs) {
      const Metrics& m = run.metrics;
      under += m.at("refraction_err_max_deg") < 0.5 ? 1 : 0;
      rmse_psi += m.at("slope_rmse_psi") / 10.0;
      rmse_theta += m.at("slope_rmse_theta") / 10.0;
      EXPECT_LE(m.at("grid_span_psi"), 0.1 + 1e-9);
      EXPECT_LE(m.at("grid_span_theta"), 0.1 + 1e-9);
    }
    EXPECT_GE(under, amplitude == 0.08 ? 7 : 9) << "amplitude " << amplitude;
    if (amplitude == 0.08) {
      EXPECT_LE(rmse_psi, 0.0112);
      EXPECT_LE(rmse_theta, 0.0112);
    }
  }
}

}  // namespace
}  // namespace kfw::radome
