#include "oracles/ballbeam/ball_tracker.h"

#include <cmath>
#include <sstream>
#include <string>

namespace kfw::ballbeam {

namespace {
bool positive_finite(double v) {
  return v > 0.0 && std::isfinite(v);
}
std::string num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}
}  // namespace

Expected<BallTracker> BallTracker::make(const TrackerParams& p) {
  if (!positive_finite(p.Ts_s)) return Error{"Ts must be positive (got " + num(p.Ts_s) + ")"};
  if (!positive_finite(p.Q)) return Error{"Q must be positive (got " + num(p.Q) + ")"};
  if (!positive_finite(p.R)) return Error{"R must be positive (got " + num(p.R) + ")"};
  if (!positive_finite(p.P0_pos) || !positive_finite(p.P0_vel))
    return Error{"initial covariance P0 must be positive"};
  BallTracker t;
  t.p_ = p;
  t.model_ = track_model(p.Ts_s, p.Q);
  t.lambda_ = tracking_index(p.Ts_s, p.Q, p.R);
  t.ab_ = alpha_beta(t.lambda_);
  t.K_steady_ << t.ab_.alpha, t.ab_.beta / p.Ts_s;
  return t;
}

Gaussian<2> BallTracker::initial(double x0_m) const {
  Gaussian<2> g;
  g.x << x0_m, 0.0;
  g.P << p_.P0_pos, 0.0, 0.0, p_.P0_vel;
  return g;
}

Gaussian<2> BallTracker::predict(const Gaussian<2>& out, double uc_mps2) const {
  return kfw::predict(out, model_.F, Vec<2>(model_.G * uc_mps2), model_.Qd);
}

BallTracker::Step BallTracker::update(const Gaussian<2>& prior, double y_m, bool missing) const {
  Step s;
  if (missing || !std::isfinite(y_m)) {
    s.out = prior;
    s.S = prior.P(0, 0) + p_.R;
    return s;
  }
  if (p_.kind == FilterKind::kKalman) {
    const auto u = update_scalar(prior, y_m, model_.H, p_.R);
    s.out = u.post;
    s.innovation = u.innovation(0);
    s.S = u.S(0, 0);
    s.nis = u.nis;
    s.K1 = u.K(0);
    s.K2 = u.K(1);
    s.updated = u.ok;
    return s;
  }
  // Fixed gain: x̂ = x̄ + K (y − x̄_1), P̂ = (I − K H) P̄ (I − K H)^T + K R K^T.
  const double y = y_m - prior.x(0);
  s.innovation = y;
  s.S = prior.P(0, 0) + p_.R;
  s.nis = y * y / s.S;
  s.K1 = K_steady_(0);
  s.K2 = K_steady_(1);
  s.out.x = prior.x + K_steady_ * y;
  Mat<2> IKH = Mat<2>::Identity();
  IKH.col(0) -= K_steady_;
  s.out.P = IKH * prior.P * IKH.transpose() + K_steady_ * p_.R * K_steady_.transpose();
  s.updated = true;
  return s;
}

}  // namespace kfw::ballbeam
