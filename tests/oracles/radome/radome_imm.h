// The radome-slope IMM of seed 001: one mode-matched linear KF per grid point (R̄_ψ^a, R̄_θ^b),
// each undoing its slope and filtering the Cartesian pseudo-measurement; slope estimate Σ μ^j R̄^j;
// mode-parameter renewal with gain Kp (eq. 4).
//
// Two structures (parameter `imm.structure`):
//  - axis blocks (default): the pseudo-measurement covariance is reduced to its diagonal (the exact
//    per-axis marginal variances), so each mode is three independent 3-state [p, v, a] filters with
//    scalar updates; mixing keeps the per-axis blocks of the spread terms. ~5× faster.
//  - full 9-state: one 9-state filter per mode with the full 3 × 3 converted covariance and the
//    full spread terms; the reference.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "core/scenario.h"
#include "filter/imm.h"
#include "oracles/radome/radome_model.h"

namespace kfw::radome {

enum class Structure { kAxisBlocks = 0, kFull = 1 };
// Readings of eq. 4 (radome_renewal.h): per sample with μ by grid index; per sample with μ by
// slope value; Kp per second with μ by grid index; per sample with the shift as a mode transition
// (μ, states and covariances carried to the moved grid together).
enum class Renewal { kIndex = 0, kSlope = 1, kRate = 2, kMix = 3 };

struct FilterParams {
  double Q = 100.0;                 // spectral density of w, (m/s²)²/Hz
  double tau_s = 0.5;               // target manoeuvre time constant τ
  double var_angle = 1e-6;          // R: ν_ψ, ν_θ variance, rad²
  double var_range = 1.0;           // ν_R variance assumed by the filter, m²
  double Kp = 0.0;                  // mode-parameter renewal gain (eq. 4); 0 = plain IMM
  Renewal renewal = Renewal::kMix;  // what eq. 4 does to μ, and Kp's unit (radome_renewal.h)
  double renewal_start_s = 2.0;     // no renewal during the IMM's start-up (time since init)
  double grid_min = -0.05, grid_max = 0.05;
  int n_psi = 7, n_theta = 7;
  double stay = 0.99;  // Markov p^{jj}
  double P0_pos_m2 = 1e4, P0_vel_m2ps2 = 1e6, P0_acc_m2ps4 = 100.0;
  Structure structure = Structure::kAxisBlocks;
};

// Checks cross-parameter consistency; the message names the key.
Status check(const FilterParams& p);

// One sample of the measurement stream (angles in rad; U = aircraft acceleration, m/s²).
struct Sample {
  double t_s = 0.0;
  double range_m = 0.0, psi_rad = 0.0, theta_rad = 0.0;
  double psi_a_rad = 0.0, theta_a_rad = 0.0;
  Vec<3> U = Vec<3>::Zero();
  bool has_measurement() const;
};

// What one step produced.
struct StepOutput {
  double slope_psi = 0.0, slope_theta = 0.0;    // Σ μ^j R̄^j
  double center_psi = 0.0, center_theta = 0.0;  // grid centre used in this step
  Vec<3> pos = Vec<3>::Zero();                  // combined relative position, m
  Covariance<3> P_pos = Covariance<3>::Zero();  // its covariance (spread terms included), m²
  Vec<3> innovation = Vec<3>::Zero();           // of the most probable mode
  Vec<3> S_diag = Vec<3>::Zero();
  double nis = 0.0;
  int map_mode = 0;
  bool updated = false;  // a measurement was used
  int failed_modes = 0;  // modes whose S was not positive definite
};

class RadomeImm {
 public:
  // Builds the grid and the discretised model for sample period T_s.
  static Expected<RadomeImm> create(const FilterParams& p, double T_s);

  // Initialises every mode from the first measurement (converted with the grid centre).
  void initialize(const Sample& s);
  // One IMM cycle with renewal (seed 001, Table 2 + eq. 4); `dt_s` the time since the last step.
  StepOutput step(const Sample& s, double dt_s);

  int modes() const { return n_psi_ * n_theta_; }
  int n_psi() const { return n_psi_; }
  int n_theta() const { return n_theta_; }
  // Mode j = a + n_ψ b holds slopes (R̄_ψ^a, R̄_θ^b).
  double slope_psi_of(int j) const { return center_psi_ + off_psi_[j % n_psi_]; }
  double slope_theta_of(int j) const { return center_theta_ + off_theta_[j / n_psi_]; }
  const std::vector<double>& offsets_psi() const { return off_psi_; }
  const std::vector<double>& offsets_theta() const { return off_theta_; }
  const VecX& log_mu() const { return log_mu_; }

 private:
  void set_model(double dt_s);
  void step_axis(const Sample& s, StepOutput& o);
  void step_full(const Sample& s, StepOutput& o);
  void finish(StepOutput& o);
  void combine_axis_positions(const VecX& mu);

  FilterParams p_;
  double T_s_ = 0.0, model_dt_s_ = -1.0;
  int n_psi_ = 1, n_theta_ = 1;
  std::vector<double> off_psi_, off_theta_;
  double center_psi_ = 0.0, center_theta_ = 0.0;
  double est_psi_ = 0.0, est_theta_ = 0.0;  // R̂_{k−1}
  double elapsed_s_ = 0.0;                  // since initialize()
  MarkovChain chain_;
  MatX chain_matrix_;  // chain_ as a matrix (Renewal::kMix composes it with the grid shift)
  std::optional<MarkovChain> moved_chain_;  // this step's shift ∘ chain_ (kMix, grid moved)
  VecX log_mu_;
  AxisModel axis_;
  Mat<9> F9_;
  Mat<9, 3> Gamma9_;
  Covariance<9> Q9_;
  std::array<std::vector<Gaussian<3>>, 3> axis_modes_, axis_mixed_;  // [axis][mode]
  std::vector<Gaussian<9>> full_modes_, full_mixed_;
  VecX log_lik_;
  Vec<3> combined_pos_ = Vec<3>::Zero();
  Covariance<3> combined_P_pos_ = Covariance<3>::Zero();
  // Scratch per grid line: corrected angles and their cos / sin.
  std::vector<double> cpsi_, spsi_, ctheta_, stheta_, inv1p_psi_, inv1p_theta_;
};

struct RadomeResult final : RunResult {
  int n_psi = 0, n_theta = 0;
  std::vector<double> offsets_psi, offsets_theta;  // grid offsets about the centre
  // Per step.
  std::vector<double> slope_psi, slope_theta, slope_psi_true, slope_theta_true;
  std::vector<double> center_psi, center_theta;
  std::vector<double> alpha_true_deg, alpha_meas_deg, alpha_est_deg;
  std::vector<double> psi_los_true_deg, theta_los_true_deg, psi_meas_deg, theta_meas_deg;
  std::vector<double> psi_los_est_deg, theta_los_est_deg;
  std::vector<double> x_est, y_est, z_est, x_true, y_true, z_true;
  std::vector<Covariance<3>> P_pos;  // combined covariance of (x, y, z)_est, m²
  // NEES of the combined position against the truth position (dof 3; NaN without truth).
  std::vector<double> nees;
  double nees_dof = 3.0;
  std::array<std::vector<double>, 3> innovation, S;  // most probable mode, per axis, m / m²
  std::vector<double> nis;
  std::vector<double> map_mode;
  std::vector<float> mu;  // steps × modes, row-major: mu[k * modes + j]
  std::size_t updates = 0;

  int modes() const { return n_psi * n_theta; }
  // Mode probabilities at step k (empty when out of range).
  std::vector<double> mode_probabilities(std::size_t k) const;
  // Grid slopes along ψ (or θ) at step k: centre + offsets.
  std::vector<double> grid_psi(std::size_t k) const;
  std::vector<double> grid_theta(std::size_t k) const;
  // Modes with the largest mean probability over the run, most probable first.
  std::vector<int> top_modes(int count) const;
  Dataset table() const override;
  // The 3-D pseudo-measurement NIS (most probable mode) and each axis' y/√S.
  std::vector<InnovationChannel> channels() const override;
  NeesSeries nees_series() const override { return {nees_dof, nees}; }
  std::vector<StateSeries> states() const override;
  // Fills `nees` from x/y/z_est, P_pos and x/y/z_true: e^T P^{-1} e per step.
  void compute_nees();
};

// Input columns of a dataset (angles in rad). `U` may be null (zero aircraft acceleration).
struct Inputs {
  const std::vector<double>* t = nullptr;
  const std::vector<double>* range = nullptr;
  const std::vector<double>* psi = nullptr;
  const std::vector<double>* theta = nullptr;
  const std::vector<double>* psi_a = nullptr;
  const std::vector<double>* theta_a = nullptr;
  std::array<const std::vector<double>*, 3> U{nullptr, nullptr, nullptr};
};

// Runs the IMM over a whole dataset.
Expected<RadomeResult> run_radome_imm(const Inputs& in, const FilterParams& p,
                                      const RunControl& control = {});

}  // namespace kfw::radome
