// Seed 001: the relative engagement model (9 states, three identical [p, v, a] axis blocks), the
// radome-refracted measurement, the per-mode slope correction and Cartesian pseudo-measurement,
// the spatial refraction error and the mode-parameter grid.
#pragma once

#include <vector>

#include "core/expected.h"
#include "core/types.h"

namespace kfw::radome {

// Per-axis state indices; the 9-state vector is [x, y, z, ẋ, ẏ, ż, A_Tx, A_Ty, A_Tz] (seed 001,
// eq. 1), i.e. block k of three holds quantity k for all three axes.
static constexpr int kPos = 0;
static constexpr int kVel = 1;
static constexpr int kAcc = 2;

// One axis of eq. 1: A = [[0, 1, 0], [0, 0, 1], [0, 0, −1/τ]], B = [0, −1, 0]^T, D = [0, 0, 1/τ]^T,
// discretised exactly (F = e^{A T}, Γ = ∫ e^{A s} B ds, Q by Van Loan with E[w w^T] = Q_c δ).
struct AxisModel {
  Mat<3> F;
  Vec<3> Gamma;  // multiplies the aircraft acceleration U of this axis
  Covariance<3> Q;
};

// Seed 001, eq. 1 per axis; errors name `tau` or `Q` or the sample period.
Expected<AxisModel> axis_model(double tau_s, double Qc, double T_s);

// The 9-state matrices of eq. 1 from the axis block: F ⊗ I3, Γ ⊗ I3, Q ⊗ I3 (same dynamics per
// axis).
Mat<9> full_F(const AxisModel& m);
Mat<9, 3> full_Gamma(const AxisModel& m);
Covariance<9> full_Q(const AxisModel& m);

// LOS azimuth ψ = atan2(y, x) and elevation θ = atan2(z, √(x² + y²)) of a relative position.
double los_psi(const Vec<3>& rel);
double los_theta(const Vec<3>& rel);

// Radome refraction of one angle (seed 001, eq. 2 without noise): z = λ + R (λ − λ_a).
double refract(double los_rad, double slope, double attitude_rad);
// The mode's inverse of eq. 2: λ = (z + R̄ λ_a) / (1 + R̄) (seed 001).
double undo_slope(double z_rad, double slope, double attitude_rad);

// Cartesian pseudo-measurement Y = z_R [cos θ cos ψ, cos θ sin ψ, sin θ] (seed 001, eq. 3).
Vec<3> pseudo_measurement(double range_m, double psi_rad, double theta_rad);
// Its first-order covariance J diag(σ_R², σ_ψ², σ_θ²) J^T, J = ∂Y/∂(R, ψ, θ).
Covariance<3> pseudo_covariance(double range_m, double psi_rad, double theta_rad, double var_range,
                                double var_psi, double var_theta);

// Spatial refraction (boresight) error α = acos(cos(R_θ(θ − θ_a)) cos(R_ψ(ψ − ψ_a))) (seed 001,
// Sec. 2.1), radians.
double refraction_error(double slope_psi, double slope_theta, double psi_los, double theta_los,
                        double psi_a, double theta_a);

// Grid of mode parameters R̄^a = min + (a − 1)(max − min)/(n − 1) (seed 001, eq. 6); n = 1 gives the
// midpoint.
std::vector<double> grid_axis(double min, double max, int n);

}  // namespace kfw::radome
