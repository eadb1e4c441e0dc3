#include "oracles/radome/radome_model.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "filter/discretize.h"

namespace kfw::radome {

Expected<AxisModel> axis_model(double tau_s, double Qc, double T_s) {
  if (!(tau_s > 0.0) || !std::isfinite(tau_s)) {
    return Error{"tau must be positive, got " + std::to_string(tau_s)};
  }
  if (!(Qc > 0.0) || !std::isfinite(Qc))
    return Error{"Q must be positive, got " + std::to_string(Qc)};
  MatX A = MatX::Zero(3, 3);
  A(0, 1) = 1.0;
  A(1, 2) = 1.0;
  A(2, 2) = -1.0 / tau_s;
  MatX B = MatX::Zero(3, 1);
  B(1, 0) = -1.0;
  MatX D = MatX::Zero(3, 1);
  D(2, 0) = 1.0 / tau_s;
  const MatX Qm = MatX::Constant(1, 1, Qc);
  auto d = van_loan(A, B, D, Qm, T_s);
  if (!d) return d.err();
  AxisModel m;
  m.F = d->F;
  m.Gamma = d->Gamma.col(0);
  m.Q = d->Q;
  return m;
}

namespace {
template <int C>
Mat<3 * 3, 3 * C> kron_i3(const Mat<3, C>& a) {
  Mat<9, 3 * C> out = Mat<9, 3 * C>::Zero();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < C; ++j)
      out.template block<3, 3>(3 * i, 3 * j) = a(i, j) * Mat<3>::Identity();
  }
  return out;
}
}  // namespace

Mat<9> full_F(const AxisModel& m) {
  return kron_i3<3>(m.F);
}
Mat<9, 3> full_Gamma(const AxisModel& m) {
  return kron_i3<1>(m.Gamma);
}
Covariance<9> full_Q(const AxisModel& m) {
  return kron_i3<3>(m.Q);
}

double los_psi(const Vec<3>& rel) {
  return std::atan2(rel(1), rel(0));
}
double los_theta(const Vec<3>& rel) {
  return std::atan2(rel(2), std::hypot(rel(0), rel(1)));
}

double refract(double los_rad, double slope, double attitude_rad) {
  return los_rad + slope * (los_rad - attitude_rad);
}

double undo_slope(double z_rad, double slope, double attitude_rad) {
  return (z_rad + slope * attitude_rad) / (1.0 + slope);
}

Vec<3> pseudo_measurement(double range_m, double psi_rad, double theta_rad) {
  const double ct = std::cos(theta_rad);
  return Vec<3>(range_m * ct * std::cos(psi_rad), range_m * ct * std::sin(psi_rad),
                range_m * std::sin(theta_rad));
}

Covariance<3> pseudo_covariance(double range_m, double psi_rad, double theta_rad, double var_range,
                                double var_psi, double var_theta) {
  const double cp = std::cos(psi_rad), sp = std::sin(psi_rad);
  const double ct = std::cos(theta_rad), st = std::sin(theta_rad);
  const Vec<3> dR(ct * cp, ct * sp, st);
  const Vec<3> dpsi(-range_m * ct * sp, range_m * ct * cp, 0.0);
  const Vec<3> dtheta(-range_m * st * cp, -range_m * st * sp, range_m * ct);
  Covariance<3> R = var_range * dR * dR.transpose();
  R.noalias() += var_psi * dpsi * dpsi.transpose();
  R.noalias() += var_theta * dtheta * dtheta.transpose();
  return R;
}

double refraction_error(double slope_psi, double slope_theta, double psi_los, double theta_los,
                        double psi_a, double theta_a) {
  const double c =
      std::cos(slope_theta * (theta_los - theta_a)) * std::cos(slope_psi * (psi_los - psi_a));
  return std::acos(std::clamp(c, -1.0, 1.0));
}

std::vector<double> grid_axis(double min, double max, int n) {
  if (n <= 1) return {0.5 * (min + max)};
  std::vector<double> g(static_cast<std::size_t>(n));
  for (int a = 0; a < n; ++a)
    g[static_cast<std::size_t>(a)] = min + a * (max - min) / (n - 1);
  return g;
}

}  // namespace kfw::radome
