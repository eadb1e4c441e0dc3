// Seed 000: the indirect (error-state) Kalman filter for attitude from a rate gyro and an absolute
// angle sensor. State X = [θ, b] (deg, deg/s).
#pragma once

#include <vector>

#include "core/expected.h"
#include "core/types.h"

namespace kfw::helicopter {

static constexpr int kTheta = 0;
static constexpr int kBias = 1;

struct Model {
  Mat<2> F;
  Vec<2> B;
  Vec<2> G;
  Mat<1, 2> H;
};

// Constant bias (γ = 0, eq. 5–7) or slowly varying bias (γ > 0, eq. 12):
// F = [[1, -Ts], [0, 1-γ]], B = [Ts, γ]^T, G = [-Ts, 0]^T, H = [1, 0].
Model model(double Ts_s, double gamma);

// β = m Ts² N_ω / N_θ (seed 000, eq. 11).
double beta(int m, double Ts_s, double N_omega, double N_theta);
// p11⁻/N_θ = √β (√(1 + β/4) + √β/2) (seed 000, eq. 11).
double p11_over_R(double beta);
// k1 = (p11⁻/N_θ) / (1 + p11⁻/N_θ), k2 = 0 (seed 000, eq. 11).
double k1_closed_form(double beta);

struct SteadyGain {
  double k1 = 0.0;
  double k2 = 0.0;
  double p11_pred = 0.0;  // P11⁻ at the angle-sample instants, deg²
  double p11_post = 0.0;
};

// Steady-state gain by the DARE of the m-step model: F^m, Q_m = Σ F^i G N_ω G^T F^iT (the exact
// lumping of m gyro propagations between angle updates).
Expected<SteadyGain> steady_gain_dare(int m, double Ts_s, double gamma, double N_omega,
                                      double N_theta);

struct GainCurve {
  std::vector<double> beta, k1, p11_over_R;
};
// k1(β) and p11⁻/N_θ(β) on n log-spaced β values (seed 000, Fig. 3).
GainCurve gain_curve(double beta_lo, double beta_hi, int n);

}  // namespace kfw::helicopter
