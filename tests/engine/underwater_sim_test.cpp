// Tests of the seed 004 simulator (tests/oracles/underwater/underwater_sim.h).
#include "oracles/underwater/underwater_sim.h"

#include <gtest/gtest.h>

#include <cmath>

namespace kfw::underwater {
namespace {

std::size_t count(const Dataset& d, const char* name) {
  std::size_t n = 0;
  for (double v : d.col(name))
    n += std::isfinite(v) ? 1 : 0;
  return n;
}

TEST(UnderwaterSim, AsynchronousClocksFollowTable3Periods) {
  SimParams p;
  p.duration_s = 10.0;
  const Dataset d = simulate(p);
  // Sensor counts over 10 s: one sample at t = 0 and every period after it.
  EXPECT_EQ(count(d, "dvl_u"), 51u);
  EXPECT_EQ(count(d, "ahrs_psi"), 1001u);
  EXPECT_EQ(count(d, "range1"), 101u);
  EXPECT_EQ(count(d, "depth"), 501u);
  // Without jitter the four ranges share their instants, and depth lands on them too.
  const auto& r1 = d.col("range1");
  const auto& r4 = d.col("range4");
  const auto& dep = d.col("depth");
  for (std::size_t k = 0; k < d.rows(); ++k) {
    EXPECT_EQ(std::isfinite(r1[k]), std::isfinite(r4[k]));
    if (std::isfinite(r1[k])) {
      EXPECT_TRUE(std::isfinite(dep[k]));
    }
  }
  // One row per measurement time: strictly increasing.
  const auto& t = d.col("t");
  for (std::size_t k = 1; k < t.size(); ++k)
    ASSERT_GT(t[k], t[k - 1]);
}

TEST(UnderwaterSim, SynchronousClockSamplesEverySensorEveryRow) {
  SimParams p;
  p.duration_s = 20.0;
  p.synchronous = true;
  p.dt_sync_s = 0.1;
  const Dataset d = simulate(p);
  EXPECT_EQ(d.rows(), 201u);
  for (const char* c : {"dvl_u", "ahrs_psi", "range1", "range2", "range3", "range4", "depth"}) {
    EXPECT_EQ(count(d, c), d.rows()) << c;
  }
}

// Table 2: the intervals are Δt + n_t with n_t ~ N(0, σ_t).
TEST(UnderwaterSim, TimingJitterHasTheRequestedSigma) {
  SimParams p;
  p.duration_s = 600.0;
  p.synchronous = true;
  p.dt_sync_s = 0.1;
  p.sigma_t_s = 0.005;
  const Dataset d = simulate(p);
  const auto& t = d.col("t");
  double s = 0, s2 = 0;
  const double n = static_cast<double>(t.size() - 1);
  for (std::size_t k = 1; k < t.size(); ++k) {
    const double dt = t[k] - t[k - 1];
    s += dt;
    s2 += dt * dt;
  }
  const double mean = s / n, sd = std::sqrt(s2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.1, 0.0005);
  EXPECT_NEAR(sd, 0.005, 0.0003);
}

// Without noise, each measurement is exactly the truth at its own instant (Tables 4–6).
TEST(UnderwaterSim, NoiseFreeMeasurementsEqualTruth) {
  SimParams p;
  p.duration_s = 30.0;
  p.sigma_t_s = 0.003;
  p.velocity_sigma.setZero();
  p.sigma_range_m = p.sigma_depth_m = p.sigma_corr_m = 0.0;
  p.outliers = 0;
  const Dataset d = simulate(p);
  const auto &x = d.col("x_true"), &y = d.col("y_true"), &z = d.col("z_true");
  const char* names[] = {"range1", "range2", "range3", "range4"};
  std::size_t checked = 0;
  for (std::size_t k = 0; k < d.rows(); ++k) {
    const Vec<3> X(x[k], y[k], z[k]);
    for (int b = 0; b < kBeacons; ++b) {
      const double r = d.col(names[b])[k];
      if (!std::isfinite(r)) continue;
      EXPECT_NEAR(r, (beacons()[static_cast<std::size_t>(b)] - X).norm(), 1e-12);
      ++checked;
    }
    if (std::isfinite(d.col("depth")[k])) {
      EXPECT_DOUBLE_EQ(d.col("depth")[k], z[k]);
    }
  }
  EXPECT_GT(checked, 1000u);
}

// Constant commands u, r (w = 0) drive a circle of radius u/r from the origin, heading north.
TEST(UnderwaterSim, CommandTrajectoryIsTheClosedFormCircle) {
  SimParams p;
  p.duration_s = 20.0;
  p.command << 0.5, 0.0, 0.0, 0.0, 0.0, 0.5;
  const Dataset d = simulate(p);
  const auto &t = d.col("t"), &x = d.col("x_cmd"), &y = d.col("y_cmd");
  const double u = 0.5, r = 0.5;
  for (std::size_t k = 0; k < d.rows(); k += 97) {
    EXPECT_NEAR(x[k], u / r * std::sin(r * t[k]), 1e-4) << t[k];
    EXPECT_NEAR(y[k], u / r * (1.0 - std::cos(r * t[k])), 1e-4) << t[k];
  }
}

// A general attitude exercises the full Euler kinematics: a pure pitch rate keeps roll and yaw.
TEST(UnderwaterSim, MotionModelIntegratesPitchRate) {
  Vec<6> pose = Vec<6>::Zero();
  Vec<6> vel;
  vel << 1.0, 0.0, 0.0, 0.0, 0.2, 0.0;
  for (int i = 0; i < 100; ++i)
    pose = motion_model(pose, vel, 0.01);
  EXPECT_NEAR(pose(4), 0.2, 1e-12);
  EXPECT_NEAR(pose(3), 0.0, 1e-12);
  EXPECT_NEAR(pose(5), 0.0, 1e-12);
  // Nose up (θ > 0) with z down: the vehicle climbs, z = −(1 − cos θ)/q.
  EXPECT_NEAR(pose(2), -(1.0 - std::cos(0.2)) / 0.2, 1e-5);
  EXPECT_NEAR(pose(0), std::sin(0.2) / 0.2, 1e-5);
  EXPECT_TRUE(rotation(0.3, -0.2, 1.0).isUnitary(1e-12));
}

// Table 8: exactly N samples carry ±σ_o; Table 7: n_c is shared by every range within t_gap.
TEST(UnderwaterSim, OutliersAndCorrelatedNoise) {
  SimParams p;
  p.duration_s = 60.0;
  p.synchronous = true;
  p.velocity_sigma.setZero();
  p.sigma_range_m = 0.0;
  p.sigma_corr_m = 0.2;
  p.t_gap_s = 1.0;
  p.outliers = 50;
  p.outlier_m = 1.0;
  const Dataset d = simulate(p);
  const char* out[] = {"outlier1", "outlier2", "outlier3", "outlier4"};
  const char* rng[] = {"range1", "range2", "range3", "range4"};
  int n_out = 0, plus = 0;
  for (const char* c : out) {
    for (double v : d.col(c)) {
      if (std::isfinite(v) && v != 0.0) {
        EXPECT_DOUBLE_EQ(std::abs(v), 1.0);
        ++n_out;
        plus += v > 0 ? 1 : 0;
      }
    }
  }
  EXPECT_EQ(n_out, 50);
  EXPECT_GT(plus, 10);
  EXPECT_LT(plus, 40);
  // Clean errors: equal across beacons at an instant, constant inside a t_gap window.
  const auto &x = d.col("x_true"), &y = d.col("y_true"), &z = d.col("z_true"), &t = d.col("t");
  double window_value = 0.0;
  long window = -1;
  for (std::size_t k = 0; k < d.rows(); ++k) {
    const Vec<3> X(x[k], y[k], z[k]);
    for (int b = 0; b < kBeacons; ++b) {
      const double e =
          d.col(rng[b])[k] - d.col(out[b])[k] - (beacons()[static_cast<std::size_t>(b)] - X).norm();
      const long w = static_cast<long>(t[k] / 1.0);
      if (w != window) {
        window = w;
        window_value = e;
      }
      EXPECT_NEAR(e, window_value, 1e-9) << "t = " << t[k];
    }
  }
}

TEST(UnderwaterSim, SameSeedSameData) {
  SimParams p;
  p.duration_s = 5.0;
  p.sigma_t_s = 0.002;
  const Dataset a = simulate(p), b = simulate(p);
  ASSERT_EQ(a.rows(), b.rows());
  for (std::size_t c = 0; c < a.columns.size(); ++c) {
    for (std::size_t k = 0; k < a.rows(); ++k) {
      const double u = a.columns[c][k], v = b.columns[c][k];
      ASSERT_TRUE((std::isnan(u) && std::isnan(v)) || u == v);
    }
  }
  p.seed = 5;
  EXPECT_NE(simulate(p).col("range1")[0], a.col("range1")[0]);
}
// Each uncertainty has its own random stream: switching the correlated range noise on, or changing
// its window, leaves the motion, the DVL, the AHRS and the depth noise draw for draw the same (a
// shared std::normal_distribution would pass its cached second draw from one stream to the next).
TEST(UnderwaterSim, StreamsAreIndependent) {
  SimParams base;
  base.duration_s = 30.0;
  base.synchronous = true;
  base.sigma_corr_m = 0.0;
  const Dataset a = simulate(base);
  for (double t_gap : {1.0, 0.7}) {
    SimParams p = base;
    p.sigma_corr_m = 0.2;
    p.t_gap_s = t_gap;
    const Dataset b = simulate(p);
    ASSERT_EQ(a.rows(), b.rows());
    for (const char* c : {"x_true", "z_true", "dvl_u", "dvl_w", "ahrs_psi", "ahrs_r", "depth"}) {
      for (std::size_t k = 0; k < a.rows(); ++k) {
        ASSERT_EQ(a.col(c)[k], b.col(c)[k]) << c << " row " << k << ", t_gap " << t_gap;
      }
    }
  }
  // Sensor noise off: the vehicle moves exactly as before.
  SimParams quiet = base;
  quiet.velocity_sigma.setZero();
  quiet.sigma_range_m = quiet.sigma_depth_m = 0.0;
  quiet.outliers = 0;
  const Dataset q = simulate(quiet);
  for (const char* c : {"x_true", "y_true", "z_true", "psi_true"}) {
    for (std::size_t k = 0; k < a.rows(); ++k)
      ASSERT_EQ(a.col(c)[k], q.col(c)[k]) << c << " row " << k;
  }
}

}  // namespace
}  // namespace kfw::underwater
