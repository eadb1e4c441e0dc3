#include "scenarios/helicopter/indirect_kf.h"

#include <cmath>

#include "core/kalman_filter.h"
#include "scenarios/helicopter/helicopter_model.h"

namespace kfw::helicopter {

Dataset HelicopterResult::table() const {
  Dataset d;
  d.source = "helicopter run";
  d.names = {"t",  "theta", "bias",       "P11", "P22", "angle", "truth",
             "gyro", "innovation", "S",  "k1",  "k2",  "nis"};
  d.columns = {t, theta, bias, P11, P22, angle, truth, gyro, innovation, S, k1, k2, nis};
  return d;
}

HelicopterResult run_indirect_kf(const std::vector<double>& t, const std::vector<double>& gyro,
                                 const std::vector<double>& angle, const FilterParams& p,
                                 const RunControl& control) {
  HelicopterResult r;
  const std::size_t n = t.size();
  r.t = t;
  r.gyro = gyro;
  r.angle = angle;
  r.theta.resize(n);
  r.bias.resize(n);
  r.P11.resize(n);
  r.P22.resize(n);
  r.innovation.assign(n, kNoSample);
  r.S.assign(n, kNoSample);
  r.k1.assign(n, kNoSample);
  r.k2.assign(n, kNoSample);
  r.nis.assign(n, kNoSample);
  if (n == 0) return r;

  Gaussian<2> g;
  g.x << (std::isfinite(angle[0]) ? angle[0] : 0.0), 0.0;
  g.P << p.P0_theta, 0.0, 0.0, p.P0_bias;
  const Mat<1, 2> H(1.0, 0.0);
  const double one_minus_gamma = 1.0 - p.gamma;
  double last_gyro = 0.0;
  std::size_t gyro_missing = 0;
  const auto m = static_cast<std::size_t>(p.m < 1 ? 1 : p.m);
  std::size_t next_update = 0;  // the angle sensor's clock: every m-th sample

  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0) {
      // Seed 000 eq. 5–7 (γ = 0) / eq. 12 (γ > 0) with this step's Ts.
      const double Ts = t[k] - t[k - 1];
      const double w = gyro[k - 1];
      if (std::isfinite(w)) {
        last_gyro = w;
      } else {
        ++gyro_missing;
      }
      Mat<2> F;
      F << 1.0, -Ts, 0.0, one_minus_gamma;
      const Vec<2> Bu(Ts * last_gyro, p.gamma * last_gyro);
      Covariance<2> Q;
      Q << Ts * Ts * p.N_omega, 0.0, 0.0, 0.0;
      g = predict(g, F, Bu, Q);
    }
    if (k == next_update) {
      next_update += m;
      if (std::isfinite(angle[k])) {
        const auto u = update_scalar(g, angle[k], H, p.N_theta);
        r.innovation[k] = u.innovation(0);
        r.S[k] = u.S(0, 0);
        if (u.ok) {
          g = u.post;
          r.k1[k] = u.K(0, 0);
          r.k2[k] = u.K(1, 0);
          r.nis[k] = u.nis;
          ++r.updates;
        }
      }
    }
    r.theta[k] = g.x(kTheta);
    r.bias[k] = g.x(kBias);
    r.P11[k] = g.P(0, 0);
    r.P22[k] = g.P(1, 1);
    if ((k & 0xFFFF) == 0xFFFF && control.cancelled()) break;
  }
  if (gyro_missing) {
    r.warnings.push_back(std::to_string(gyro_missing) +
                         " gyro samples missing: the previous rate was held");
  }
  return r;
}

}  // namespace kfw::helicopter
