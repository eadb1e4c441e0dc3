// The radome IMM against identities: with one mode it is the plain Kalman filter on the
// slope-corrected pseudo-measurement (both structures), and the axis blocks equal the full 9-state
// filter when the converted covariance is diagonal.
#include "oracles/radome/radome_imm.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "common/matrix_matchers.h"
#include "filter/kalman_filter.h"
#include "oracles/radome/radome_sim.h"

namespace kfw::radome {
namespace {

std::vector<Sample> simulated(double amplitude) {
  SimParams sp;
  sp.amplitude = amplitude;
  sp.duration_s = 20.0;
  auto d = simulate(sp);
  EXPECT_TRUE(d.ok());
  std::vector<Sample> out;
  for (std::size_t k = 0; k < d->rows(); ++k) {
    Sample s;
    s.t_s = d->col("t")[k];
    s.range_m = d->col("range_m")[k];
    s.psi_rad = d->col("psi_rad")[k];
    s.theta_rad = d->col("theta_rad")[k];
    s.psi_a_rad = d->col("psi_a_rad")[k];
    s.theta_a_rad = d->col("theta_a_rad")[k];
    s.U = Vec<3>(0.3 * std::sin(s.t_s), -0.2, 0.1);  // exercise the input path too
    out.push_back(s);
  }
  return out;
}

FilterParams one_mode(double slope, Structure st) {
  FilterParams p;
  p.grid_min = p.grid_max = slope;
  p.n_psi = p.n_theta = 1;
  p.structure = st;
  p.Kp = 0.45;  // one mode: R̂ = centre, so renewal must not move anything
  return p;
}

TEST(RadomeImm, OneModeAxisBlocksEqualThreePlainKalmanFilters) {
  const double slope = 0.02, T = 0.05;
  const auto s = simulated(0.0);
  const FilterParams p = one_mode(slope, Structure::kAxisBlocks);
  auto imm = RadomeImm::create(p, T);
  ASSERT_TRUE(imm.ok()) << imm.error();
  imm->initialize(s[0]);
  auto m = axis_model(p.tau_s, p.Q, T);
  ASSERT_TRUE(m.ok());
  const Vec<3> Y0 =
      pseudo_measurement(s[0].range_m, undo_slope(s[0].psi_rad, slope, s[0].psi_a_rad),
                         undo_slope(s[0].theta_rad, slope, s[0].theta_a_rad));
  Gaussian<3> kf[3];
  for (int ax = 0; ax < 3; ++ax) {
    kf[ax].x = Vec<3>(Y0(ax), 0, 0);
    kf[ax].P = Vec<3>(p.P0_pos_m2, p.P0_vel_m2ps2, p.P0_acc_m2ps4).asDiagonal();
  }
  const Mat<1, 3> H(1, 0, 0);
  const double g = 1.0 / ((1 + slope) * (1 + slope));
  for (std::size_t k = 1; k < s.size(); ++k) {
    const StepOutput o = imm->step(s[k], T);
    const double psi = undo_slope(s[k].psi_rad, slope, s[k].psi_a_rad);
    const double th = undo_slope(s[k].theta_rad, slope, s[k].theta_a_rad);
    const Vec<3> Y = pseudo_measurement(s[k].range_m, psi, th);
    const Covariance<3> R =
        pseudo_covariance(s[k].range_m, psi, th, p.var_range, p.var_angle * g, p.var_angle * g);
    for (int ax = 0; ax < 3; ++ax) {
      kf[ax] = predict(kf[ax], m->F, Vec<3>(m->Gamma * s[k].U(ax)), m->Q);
      const auto u = update_scalar(kf[ax], Y(ax), H, R(ax, ax));
      ASSERT_TRUE(u.ok);
      kf[ax] = u.post;
      ASSERT_NEAR(o.pos(ax), kf[ax].x(0), 1e-6 * (1 + std::abs(kf[ax].x(0)))) << k;
      ASSERT_NEAR(o.P_pos(ax, ax), kf[ax].P(0, 0), 1e-6 * kf[ax].P(0, 0)) << k;
      // One mode: no spread term, so the axes stay uncorrelated.
      ASSERT_EQ(o.P_pos(ax, (ax + 1) % 3), 0.0) << k;
      ASSERT_NEAR(o.innovation(ax), u.innovation(0), 1e-6 * (1 + std::abs(u.innovation(0))));
    }
    ASSERT_EQ(o.slope_psi, slope);
    ASSERT_EQ(o.center_theta, slope);
  }
}

TEST(RadomeImm, OneModeFullEqualsThePlain9StateKalmanFilter) {
  const double slope = -0.03, T = 0.05;
  const auto s = simulated(0.0);
  const FilterParams p = one_mode(slope, Structure::kFull);
  auto imm = RadomeImm::create(p, T);
  ASSERT_TRUE(imm.ok());
  imm->initialize(s[0]);
  auto m = axis_model(p.tau_s, p.Q, T);
  const Mat<9> F = full_F(*m);
  const Mat<9, 3> G = full_Gamma(*m);
  const Covariance<9> Q = full_Q(*m);
  Gaussian<9> kf;
  kf.x.setZero();
  kf.x.head<3>() = pseudo_measurement(s[0].range_m, undo_slope(s[0].psi_rad, slope, s[0].psi_a_rad),
                                      undo_slope(s[0].theta_rad, slope, s[0].theta_a_rad));
  kf.P.setZero();
  kf.P.diagonal() << Vec<3>::Constant(p.P0_pos_m2), Vec<3>::Constant(p.P0_vel_m2ps2),
      Vec<3>::Constant(p.P0_acc_m2ps4);
  Mat<3, 9> H = Mat<3, 9>::Zero();
  H.leftCols<3>().setIdentity();
  const double g = 1.0 / ((1 + slope) * (1 + slope));
  for (std::size_t k = 1; k < s.size(); ++k) {
    const StepOutput o = imm->step(s[k], T);
    const double psi = undo_slope(s[k].psi_rad, slope, s[k].psi_a_rad);
    const double th = undo_slope(s[k].theta_rad, slope, s[k].theta_a_rad);
    const auto u = update(
        predict(kf, F, Vec<9>(G * s[k].U), Q), pseudo_measurement(s[k].range_m, psi, th), H,
        pseudo_covariance(s[k].range_m, psi, th, p.var_range, p.var_angle * g, p.var_angle * g));
    ASSERT_TRUE(u.ok);
    kf = u.post;
    ASSERT_TRUE(kfw::testing::MatricesNear(o.pos, kf.x.head<3>(), 1e-9 * kf.x.head<3>().norm()))
        << k;
    ASSERT_NEAR(o.nis, u.nis, 1e-9 * (1 + u.nis));
    const Covariance<3> P = kf.P.topLeftCorner<3, 3>();
    ASSERT_TRUE(kfw::testing::MatricesNear(o.P_pos, P, 1e-9 * P.norm())) << k;
  }
}

TEST(RadomeImm, CombinedPositionCovarianceIsSymmetricPositiveDefinite) {
  // 49 modes, both structures: the combined (x, y, z) block with its spread terms.
  const auto s = simulated(0.05);
  for (Structure st : {Structure::kAxisBlocks, Structure::kFull}) {
    FilterParams p;
    p.structure = st;
    auto imm = RadomeImm::create(p, 0.05);
    ASSERT_TRUE(imm.ok());
    imm->initialize(s[0]);
    double cross = 0.0;
    for (std::size_t k = 1; k < s.size(); ++k) {
      const StepOutput o = imm->step(s[k], 0.05);
      ASSERT_TRUE(o.P_pos.allFinite()) << k;
      ASSERT_LE((o.P_pos - o.P_pos.transpose()).norm(), 1e-12 * o.P_pos.norm()) << k;
      ASSERT_EQ(Eigen::LLT<Covariance<3>>(o.P_pos).info(), Eigen::Success) << k;
      cross = std::max(cross, std::abs(o.P_pos(0, 1)) + std::abs(o.P_pos(1, 2)));
    }
    // Several modes disagree on the position: the spread term correlates the axes.
    EXPECT_GT(cross, 0.0) << static_cast<int>(st);
  }
}

TEST(RadomeImm, MissingMeasurementOnlyPredicts) {
  const auto s = simulated(0.05);
  FilterParams p;
  auto imm = RadomeImm::create(p, 0.05);
  ASSERT_TRUE(imm.ok());
  imm->initialize(s[0]);
  for (std::size_t k = 1; k < 40; ++k)
    imm->step(s[k], 0.05);
  const VecX before = imm->log_mu();
  Sample gap = s[40];
  gap.psi_rad = std::nan("");
  const StepOutput o = imm->step(gap, 0.05);
  EXPECT_FALSE(o.updated);
  EXPECT_TRUE(o.pos.allFinite());
  // No measurement: μ_k = c̄ (the Markov prediction), still a distribution.
  EXPECT_NEAR(imm->log_mu().array().exp().sum(), 1.0, 1e-12);
  EXPECT_FALSE(imm->log_mu().isApprox(before));
}

TEST(RadomeImm, CreateRejectsInconsistentParameters) {
  FilterParams p;
  p.grid_min = 0.1;
  p.grid_max = -0.1;
  auto f = RadomeImm::create(p, 0.05);
  ASSERT_FALSE(f.ok());
  EXPECT_NE(f.error().find("grid.min"), std::string::npos);
  p = FilterParams{};
  p.stay = 0.0;
  EXPECT_FALSE(RadomeImm::create(p, 0.05).ok());
  p = FilterParams{};
  p.n_theta = 0;
  EXPECT_FALSE(RadomeImm::create(p, 0.05).ok());
}

}  // namespace
}  // namespace kfw::radome
