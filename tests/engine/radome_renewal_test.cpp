// Mode-parameter renewal (seed 001, eq. 4) keeping each mode probability with its slope: no shift
// is the identity, a whole grid step moves the mass one index, half a step splits it, the total
// is kept and so is the mean slope while the mass stays inside the grid; the shift as a mode
// transition moves μ as the remapping does. The readings on presets/radome.json:
// radome_preset_test.cpp; Figs. 7–9: ImmModelRadome.TheBuiltInsRenewalTestHoldsForTheFile.
#include "oracles/radome/radome_renewal.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace kfw::radome
