// Seed 003's closed loop, the oracle of presets/ballbeam.json (tests/oracles/ballbeam): Table 1's
// loop settles on the set point, contact losses follow their rate and burst length, the time the
// ball leaves the beam is the first sample beyond the half length, and the settled gain ends the
// longest unbroken run of updates. The seed's numbers on the model file: ballbeam_preset_test.cpp.
#include "oracles/ballbeam/ballbeam_loop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace kfw::ballbeam {
namespace {

TEST(BallbeamLoop, NoiseFreeStepSettlesOnTheSetpoint) {
  LoopParams p;
  auto t = BallTracker::make(TrackerParams{});
  ASSERT_TRUE(t.ok());
  LoopOptions clean;
  clean.impulsive = false;
  const LoopTrace tr = run_closed_loop(p, *t, make_disturbances(loop_steps(p), p), clean);
  ASSERT_FALSE(tr.diverged);
  ASSERT_EQ(tr.t.size(), 1501u);
  // The integral action of Table 1's PID removes the a2·x load: zero steady-state error.
  EXPECT_NEAR(tr.x_true.back(), p.setpoint_m, 1e-3);
  EXPECT_NEAR(tr.theta.back(), 0.0, 1e-3);
  EXPECT_EQ(tr.lost_samples, 0u);
}

TEST(BallbeamLoop, DisturbancesFollowRateAndBurst) {
  LoopParams p;
  p.contact_loss_rate = 0.02;
  p.burst = 4;
  const std::size_t n = 200000;
  const Disturbances d = make_disturbances(n, p);
  std::size_t lost = 0, bursts = 0;
  for (std::size_t k = 0; k < n; ++k) {
    lost += d.lost[k];
    bursts += d.lost[k] && (k == 0 || !d.lost[k - 1]);
    if (d.lost[k]) {
      ASSERT_LE(std::abs(d.spike_m[k]), p.sensor.beam_length_m / 2);
    }
  }
  // A burst starts with probability r per free sample and lasts b samples on average:
  // lost fraction r b / (1 + r b). Adjacent bursts merge, so count-based burst length is ≥ b.
  const double expected = 0.02 * 4 / (1 + 0.02 * 4);
  EXPECT_NEAR(static_cast<double>(lost) / n, expected, 0.1 * expected);
  EXPECT_GT(static_cast<double>(lost) / bursts, 3.6);
  p.contact_loss_rate = 0.0;
  const Disturbances none = make_disturbances(100, p);
  for (char c : none.lost)
    EXPECT_EQ(c, 0);
  // Rate does not touch the Gaussian noise stream.
  p.contact_loss_rate = 0.5;
  EXPECT_EQ(make_disturbances(100, p).noise_m, none.noise_m);
}

TEST(BallbeamLoop, LeftBeamAtIsTheFirstSampleBeyondTheHalfLength) {
  const double nan = std::nan("");
  const std::vector<double> t{0.0, 0.1, 0.2, 0.3, 0.4, 0.5};
  EXPECT_EQ(left_beam_at(t, {0.0, 0.2, -0.2, nan, -0.21, 0.3}, 0.2), 0.4);  // |x| = L/2 is on
  EXPECT_TRUE(std::isnan(left_beam_at(t, {0.0, 0.1, nan, 0.2, -0.2, 0.0}, 0.2)));
  EXPECT_TRUE(std::isnan(left_beam_at({}, {}, 0.2)));
  EXPECT_EQ(SensorModel{}.half_length_m(), 0.2);  // the 0.4 m wire runs the whole beam
}

TEST(BallbeamLoop, SettledGainEndsTheLongestUnbrokenRunOfUpdates) {
  const double nan = std::nan("");
  LoopTrace tr;
  tr.K1 = {0.9, 0.5, nan, 0.8, 0.6, 0.4, nan, 0.7, 0.45, 0.41, nan, 0.6};
  tr.K2 = tr.K1;
  SettledGain g = settled_gain(tr);
  EXPECT_EQ(g.K1, 0.41);  // runs of 2, 3, 3 (the latest wins) and 1
  EXPECT_EQ(g.K2, 0.41);
  EXPECT_EQ(g.run, 3u);
  tr.K1 = tr.K2 = {nan, nan};
  g = settled_gain(tr);
  EXPECT_TRUE(std::isnan(g.K1));
  EXPECT_EQ(g.run, 0u);
}
}  // namespace
}  // namespace kfw::ballbeam
