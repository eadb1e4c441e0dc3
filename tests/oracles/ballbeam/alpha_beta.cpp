#include "oracles/ballbeam/alpha_beta.h"

#include <algorithm>
#include <cmath>

#include "filter/dare.h"

namespace kfw::ballbeam {

TrackModel track_model(double Ts_s, double Q) {
  TrackModel m;
  m.F << 1.0, Ts_s, 0.0, 1.0;
  m.G << 0.5 * Ts_s * Ts_s, Ts_s;
  m.H << 1.0, 0.0;
  m.Qd = m.G * Q * m.G.transpose();
  return m;
}

double tracking_index(double Ts_s, double Q, double R) {
  return Ts_s * Ts_s * std::sqrt(Q / R);
}

AlphaBeta alpha_beta(double lambda) {
  // With r = √(λ² + 8λ): (λ+4)r − λ² − 8λ = r (λ + 4 − r) and λ + 4 − r = 16 / (λ + 4 + r),
  // so α = 2r / (λ + 4 + r); likewise λ(λ + 4 − r)/4 = 4λ / (λ + 4 + r) = β. Same values as the
  // printed formulas, without the cancellation that loses digits for small λ.
  AlphaBeta ab;
  if (!(lambda > 0.0)) return ab;
  const double r = std::sqrt(lambda * lambda + 8.0 * lambda);
  const double d = lambda + 4.0 + r;
  ab.alpha = 2.0 * r / d;
  ab.beta = 4.0 * lambda / d;
  return ab;
}

Expected<SteadyTrackGain> steady_gain_dare(double Ts_s, double Q, double R) {
  if (!(Ts_s > 0.0) || !std::isfinite(Ts_s)) return Error{"Ts must be positive and finite"};
  if (!(Q > 0.0) || !std::isfinite(Q)) return Error{"Q must be positive and finite"};
  if (!(R > 0.0) || !std::isfinite(R)) return Error{"R must be positive and finite"};
  const TrackModel m = track_model(Ts_s, Q);
  MatX Rm(1, 1);
  Rm(0, 0) = R;
  auto ss = solve_dare(m.F, m.H, m.Qd, Rm);
  if (!ss) return Error{"ball tracking DARE: " + ss.error()};
  SteadyTrackGain g;
  g.K = ss->K;
  g.alpha = g.K(0);
  g.beta = g.K(1) * Ts_s;
  g.P_pred = ss->P_pred;
  g.P_post = ss->P_post;
  return g;
}

GainCurve gain_curve(double lambda_lo, double lambda_hi, int n) {
  GainCurve c;
  if (n < 2 || !(lambda_lo > 0.0) || !(lambda_hi > lambda_lo)) return c;
  const double l0 = std::log10(lambda_lo), l1 = std::log10(lambda_hi);
  for (int i = 0; i < n; ++i) {
    const double lam = std::pow(10.0, l0 + (l1 - l0) * i / (n - 1));
    const AlphaBeta ab = alpha_beta(lam);
    c.lambda.push_back(lam);
    c.alpha.push_back(ab.alpha);
    c.beta.push_back(ab.beta);
  }
  return c;
}

}  // namespace kfw::ballbeam
