#include "oracles/helicopter/helicopter_model.h"

#include <cmath>

#include "filter/dare.h"

namespace kfw::helicopter {

Model model(double Ts_s, double gamma) {
  Model md;
  md.F << 1.0, -Ts_s, 0.0, 1.0 - gamma;
  md.B << Ts_s, gamma;
  md.G << -Ts_s, 0.0;
  md.H << 1.0, 0.0;
  return md;
}

double beta(int m, double Ts_s, double N_omega, double N_theta) {
  return static_cast<double>(m) * Ts_s * Ts_s * N_omega / N_theta;
}

double p11_over_R(double b) {
  const double sb = std::sqrt(b);
  return sb * (std::sqrt(1.0 + 0.25 * b) + 0.5 * sb);
}

double k1_closed_form(double b) {
  const double p = p11_over_R(b);
  return p / (1.0 + p);
}

Expected<SteadyGain> steady_gain_dare(int m, double Ts_s, double gamma, double N_omega,
                                      double N_theta) {
  if (m < 1) return Error{"m must be at least 1"};
  const Model md = model(Ts_s, gamma);
  const Mat<2> Q1 = md.G * N_omega * md.G.transpose();
  Mat<2> Fm = Mat<2>::Identity();
  Mat<2> Qm = Mat<2>::Zero();
  for (int i = 0; i < m; ++i) {
    Qm = md.F * Qm * md.F.transpose() + Q1;
    Fm = md.F * Fm;
  }
  MatX R(1, 1);
  R(0, 0) = N_theta;
  auto ss = solve_dare(Fm, md.H, Qm, R);
  if (!ss) return ss.err();
  SteadyGain g;
  g.k1 = ss->K(0, 0);
  g.k2 = ss->K(1, 0);
  g.p11_pred = ss->P_pred(0, 0);
  g.p11_post = ss->P_post(0, 0);
  return g;
}

GainCurve gain_curve(double beta_lo, double beta_hi, int n) {
  GainCurve c;
  const double l0 = std::log10(beta_lo), l1 = std::log10(beta_hi);
  for (int i = 0; i < n; ++i) {
    const double b = std::pow(10.0, l0 + (l1 - l0) * i / (n - 1));
    c.beta.push_back(b);
    c.k1.push_back(k1_closed_form(b));
    c.p11_over_R.push_back(p11_over_R(b));
  }
  return c;
}

}  // namespace kfw::helicopter
