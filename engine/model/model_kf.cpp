// The Kalman filter of a linear model and the extended Kalman filter of any model: one loop, the
// EKF linearising f and h where the KF reads F and H (on a linear model they are the same
// arithmetic). Joseph-form updates (kalman_filter.h).
#include <Eigen/Cholesky>
#include <cmath>

#include "filter/covariance_check.h"
#include "model/model_filter_detail.h"

namespace kfw::model::detail {

namespace {

// One channel's update at row k (seed 000 eq. 8–9 generalised): S = H P Hᵀ + R,
// K = P Hᵀ S⁻¹, x += K y, P = (I − K H) P (I − K H)ᵀ + K R Kᵀ. An S that is not positive
// definite skips the update (counted); a gated update records y and S only.
template <int N>
void update(Context& ctx, std::size_t c, std::size_t k, typename Types<N>::VecN& x,
            typename Types<N>::MatN& P) {
  using T = Types<N>;
  const ChannelSpec& cs = ctx.spec.channels[c];
  ModelEval::Channel& ch = ctx.ev.channel(c);
  ChannelSeries& out = ctx.r.chans[c];
  const Eigen::Index n = x.size();
  const int m = cs.size();
  if (m == 1) {
    // Scalar measurement: no factorisation (kalman_filter.h, update_scalar).
    typename T::VecN h(n);
    for (Eigen::Index i = 0; i < n; ++i)
      h(i) = ch.H(0, i);
    typename T::VecN PHt;
    PHt.noalias() = P * h;
    const double S = h.dot(PHt) + ch.R(0, 0);
    const double zhat = cs.linear ? h.dot(x) : ch.hx(0);
    const double y = wrap(ctx.z_buf[0] - zhat, cs.roles[0].angle);
    const Eigen::Matrix<double, 1, 1> ym(y), Sm(S);
    if (!(S > 0.0) || !std::isfinite(S)) {
      ++out.skipped;
      return;
    }
    const double nis = y * y / S;
    if (ch.gate_nis > 0.0 && nis > ch.gate_nis) {
      ++out.gated;
      ctx.record_update(c, k, ym, Sm, kNoSample, kNoSample, typename T::VecN());
      return;
    }
    const typename T::VecN K = PHt / S;
    x.noalias() += K * y;
    P.noalias() -= K * PHt.transpose();
    P.noalias() -= PHt * K.transpose();
    P.noalias() += (S * K) * K.transpose();
    debug_check_covariance(P, "a model's scalar update");
    ++out.updates;
    ctx.record_update(c, k, ym, Sm, nis, std::log(S), K);
    return;
  }
  typename T::MatMN H(m, n);
  H = ch.H;
  typename T::MatNM PHt(n, m);
  PHt.noalias() = P * H.transpose();
  typename T::MatM S(m, m);
  S.noalias() = H * PHt;
  S += ch.R;
  typename T::VecM y(m);
  for (int j = 0; j < m; ++j) {
    const double zhat = cs.linear ? H.row(j).dot(x.transpose()) : ch.hx(j);
    y(j) = wrap(ctx.z_buf[static_cast<std::size_t>(j)] - zhat,
                cs.roles[static_cast<std::size_t>(j)].angle);
  }
  Eigen::LLT<typename T::MatM> llt(S);
  if (llt.info() != Eigen::Success || !S.allFinite()) {
    ++out.skipped;
    return;
  }
  const double nis = y.dot(llt.solve(y));
  if (ch.gate_nis > 0.0 && nis > ch.gate_nis) {
    ++out.gated;
    ctx.record_update(c, k, y, S, kNoSample, kNoSample, typename T::MatNM());
    return;
  }
  double log_det = 0.0;
  for (int j = 0; j < m; ++j)
    log_det += 2.0 * std::log(llt.matrixLLT()(j, j));
  const typename T::MatNM K = llt.solve(PHt.transpose()).transpose();
  x.noalias() += K * y;
  typename T::MatN IKH = T::MatN::Identity(n, n);
  IKH.noalias() -= K * H;
  typename T::MatN tmp;
  tmp.noalias() = IKH * P;
  P.noalias() = tmp * IKH.transpose();
  typename T::MatNM KR;
  KR.noalias() = K * ch.R;
  P.noalias() += KR * K.transpose();
  P = 0.5 * (P + P.transpose()).eval();
  debug_check_covariance(P, "a model's update");
  ++out.updates;
  ctx.record_update(c, k, y, S, nis, log_det, K);
}

}  // namespace

template <int N>
Status run_kf(Context& ctx, typename Types<N>::VecN x, typename Types<N>::MatN P) {
  using T = Types<N>;
  const ModelSpec& spec = ctx.spec;
  ModelEval& ev = ctx.ev;
  const auto& t = *ctx.data.t;
  const Eigen::Index n = x.size();
  const bool nonlinear = spec.process.form == ProcessForm::kNonlinear;
  const bool q_state = spec.process.Q.dep() == Dep::kState;
  const bool q_varies = ev.process_noise_varies();
  const auto nu = static_cast<Eigen::Index>(ctx.u_held.size());
  const bool has_B = ev.B.size() > 0;
  bool any_angle = false;
  for (const auto& s : spec.states)
    any_angle = any_angle || s.angle != Angle::kNone;
  typename T::MatN F(n, n), FP(n, n);
  typename T::VecN xp(n);

  for (std::size_t k = 0; k < ctx.data.rows; ++k) {
    if (k > 0) {
      // x_{k|k−1} = F x + B u (or f(x, u)), P_{k|k−1} = F P Fᵀ + Q (F = ∂f/∂x for the EKF).
      if (auto st = ev.set_dt(t[k] - t[k - 1]); !st) return ctx.fail(k, st.error());
      ev.set_time(t[k - 1]);
      ev.set_inputs(ctx.u_held.data());
      ev.process_step();
      if (nonlinear || q_state) ev.set_state(x.data());
      if (nonlinear) {
        ev.process_f();
        ev.process_jacobian();
      }
      if (q_state) ev.process_noise();
      if (q_varies) {
        if (auto st = ctx.check_noise(k, ev.Q, "model.process.Q"); !st) return st;
      }
      F = ev.F;
      if (nonlinear) {
        xp = ev.fx;
      } else {
        xp.noalias() = F * x;
        if (has_B) {
          for (Eigen::Index j = 0; j < nu; ++j)
            xp += ev.B.col(j) * ctx.u_held[static_cast<std::size_t>(j)];
        }
      }
      x = xp;
      FP.noalias() = F * P;
      P.noalias() = FP * F.transpose();
      P += ev.Q;
      if (any_angle) {
        for (Eigen::Index i = 0; i < n; ++i)
          x(i) = wrap(x(i), spec.states[static_cast<std::size_t>(i)].angle);
      }
      if (auto st = ctx.check_finite(k, x); !st) return st;
    }
    ctx.hold_inputs(k);
    bool row_set = false;
    for (std::size_t c = 0; c < spec.channels.size(); ++c) {
      if (!ctx.channel_ready(c, k)) continue;
      const ChannelSpec& cs = spec.channels[c];
      if (!row_set) {
        ev.set_time(t[k]);
        ev.set_inputs(ctx.u_held.data());
        row_set = true;
      }
      ev.channel_step(c);
      const bool r_state = cs.R.dep() == Dep::kState;
      if (!cs.linear || r_state) ev.set_state(x.data());
      if (!cs.linear) {
        ev.channel_h(c);
        ev.channel_jacobian(c);
      }
      if (r_state) ev.channel_noise(c);
      if (ev.channel(c).R_varies) {
        if (auto st = ctx.check_noise(k, ev.channel(c).R, cs.R.key); !st) return st;
      }
      update<N>(ctx, c, k, x, P);
      if (any_angle) {
        for (Eigen::Index i = 0; i < n; ++i)
          x(i) = wrap(x(i), spec.states[static_cast<std::size_t>(i)].angle);
      }
      if (auto st = ctx.check_finite(k, x); !st) return st;
    }
    ctx.record_state(k, x, P);
    if ((k & 0xFFF) == 0xFFF && ctx.control.cancelled()) return Error{"cancelled"};
  }
  return Ok{};
}

#define KFW_MODEL_KF(N) \
  template Status run_kf<N>(Context&, typename Types<N>::VecN, typename Types<N>::MatN);
KFW_MODEL_KF(1)
KFW_MODEL_KF(2)
KFW_MODEL_KF(3)
KFW_MODEL_KF(4)
KFW_MODEL_KF(5)
KFW_MODEL_KF(6)
KFW_MODEL_KF(Eigen::Dynamic)
#undef KFW_MODEL_KF

}  // namespace kfw::model::detail
