// The model filters, one struct each, that run_steps drives (model_filter_detail.h): the Kalman
// filter of a linear model and the extended Kalman filter of any model (one filter, the EKF
// linearising f and h where the KF reads F and H; filter/ekf.h for the prediction, the Joseph-form
// update of filter/measurement_update.h), and the unscented Kalman filter (filter/ukf.h: scaled
// sigma points, circular means of angle components; sigma points redrawn before each channel
// update). A plain run has one (model_kf.cpp, model_ukf.cpp); an IMM one per mode (model/imm/).
#pragma once

#include <cmath>

#include "filter/ekf.h"
#include "filter/ukf.h"
#include "model/model_filter_detail.h"

namespace kfw::model::detail {

template <int N>
struct KalmanFilter {
  using D = Dims<N>;
  Context& ctx;
  Vec<N> x;
  Covariance<N> P;
  Eigen::Index n = x.size();
  bool nonlinear = ctx.spec.nonlinear_process();
  bool q_state = ctx.spec.process_noise_at_state();
  Covariance<N> F{n, n}, FP{n, n};
  Vec<N> fx{n};

  // x_{k|k−1} = F x + B u (or f(x, u)), P_{k|k−1} = F P Fᵀ + Q (F = ∂f/∂x for the EKF).
  Status predict(std::size_t k) {
    ModelEval& ev = ctx.ev;
    if (nonlinear || q_state) ev.set_state(x.data());
    if (nonlinear) {
      ev.process_f_jacobian();
    }
    if (q_state) ev.process_noise();
    if (ev.process_noise_varies()) {
      if (auto st = ctx.check_process_noise(k); !st) return st;
    }
    F = ev.F;
    if (nonlinear) {
      fx = ev.fx;
    } else {
      fx.noalias() = F * x;
      for (Eigen::Index j = 0; j < ev.B.cols(); ++j)
        fx += ev.B.col(j) * ctx.u_held[static_cast<std::size_t>(j)];
    }
    ekf_predict(x, P, fx, F, ev.Q, FP);
    ctx.wrap_states(x);
    return ctx.check_estimate(k, x, P);
  }

  // Channel c at row k: H (or ∂h/∂x at x_{k|k−1}), R and the innovation y = z − ẑ, ẑ = H x or
  // h(x), then the Joseph-form update (seed 000 eq. 8–9 generalised).
  Status update(std::size_t c, std::size_t k) {
    const ChannelSpec& cs = ctx.spec.channels[c];
    ModelEval& ev = ctx.ev;
    ModelEval::Channel& ch = ev.channel(c);
    const bool r_state = ch.R_at_state;
    if (!cs.linear || r_state) ev.set_state(x.data());
    if (!cs.linear) {
      ev.channel_h(c);
      ev.channel_jacobian(c);
    }
    if (r_state) ev.channel_noise(c);
    if (ch.R_varies) {
      if (auto st = ctx.check_channel_noise(c, k); !st) return st;
    }
    const bool applied =
        cs.size() == 1 ? update_scalar(c, k, ch, cs.linear) : update_vector(c, k, ch, cs);
    if (!applied) return ctx.skip(c, k, why);
    ctx.wrap_states(x);
    return ctx.check_estimate(k, x, P);
  }

  std::string why{};  // why the last update was skipped

  // Group g's samples in one stacked update (GroupScheme::kStacked, seed 004's SC), at row k's
  // prior: each member's ẑ and H at x_{k|k−1}; R the members' R on the diagonal, the group's
  // `cross` elsewhere; each member gated on its own S_ii, the rest applied together. Each
  // member's y, S_ii, NIS y²/S_ii and gain column are recorded on the row its sample arrived.
  [[gnu::noinline]] Status update_group(std::size_t g, const std::vector<Pending>& batch,
                                        std::size_t k) {
    ModelEval& ev = ctx.ev;
    ev.set_state(x.data());
    std::vector<std::size_t> use;  // batch entries with a finite ẑ
    typename D::Meas zhat(static_cast<Eigen::Index>(batch.size()));
    for (std::size_t a = 0; a < batch.size(); ++a) {
      const std::size_t c = batch[a].c;
      const ChannelSpec& cs = ctx.spec.channels[c];
      if (!cs.linear) {
        ev.channel_h(c);
        ev.channel_jacobian(c);
      }
      if (ev.channel(c).R_at_state) ev.channel_noise(c);
      if (ev.channel(c).R_varies) {
        if (auto st = ctx.check_channel_noise(c, k); !st) return st;
      }
      const auto& ch = ev.channel(c);
      const auto aa = static_cast<Eigen::Index>(a);
      zhat(aa) = cs.linear ? ch.H.row(0).dot(x.transpose()) : ch.hx(0);
      if (std::isfinite(zhat(aa))) {
        use.push_back(a);
      } else if (auto st = ctx.skip(c, batch[a].row, ctx.zhat_not_finite(c, 0, false)); !st) {
        return st;
      }
    }
    const auto m = static_cast<Eigen::Index>(use.size());
    typename D::MeasJac H(m, n);
    typename D::Meas y(m);
    typename D::MeasCov R(m, m);
    R.setConstant(ev.group(g).cross);
    for (Eigen::Index a = 0; a < m; ++a) {
      const std::size_t b = use[static_cast<std::size_t>(a)];
      const std::size_t c = batch[b].c;
      H.row(a) = ev.channel(c).H.row(0);
      R(a, a) = ev.channel(c).R(0, 0);
      y(a) = wrap(batch[b].z - zhat(static_cast<Eigen::Index>(b)), ctx.role_angle[c][0]);
    }
    typename D::Cross PHt(n, m);
    typename D::MeasCov S(m, m);
    innovation_covariance(P, H, R, PHt, S);
    std::vector<Eigen::Index> keep;
    for (Eigen::Index a = 0; a < m; ++a) {
      const Pending& q = batch[use[static_cast<std::size_t>(a)]];
      ChannelSeries& series = ctx.r.chans[q.c];
      series.y[0][q.row] = y(a);
      series.S[0][q.row] = S(a, a);
      const double gate = ev.channel(q.c).gate_nis;
      if (!(S(a, a) > 0.0) || !std::isfinite(S(a, a))) {
        if (auto st = ctx.skip(q.c, q.row, ctx.s_not_pd(q.c, S.block(a, a, 1, 1), false)); !st)
          return st;
      } else if (gate > 0.0 && y(a) * y(a) > gate * S(a, a)) {
        ++series.gated;
        series.gated_rows.push_back(q.row);
      } else {
        keep.push_back(a);
      }
    }
    if (keep.empty()) return Ok{};
    const auto mk = static_cast<Eigen::Index>(keep.size());
    typename D::MeasJac Hk(mk, n);
    typename D::Meas yk(mk);
    typename D::MeasCov Rk(mk, mk), Sk(mk, mk);
    typename D::Cross PHtk(n, mk);
    for (Eigen::Index a = 0; a < mk; ++a) {
      Hk.row(a) = H.row(keep[static_cast<std::size_t>(a)]);
      yk(a) = y(keep[static_cast<std::size_t>(a)]);
      for (Eigen::Index b = 0; b < mk; ++b)
        Rk(a, b) = R(keep[static_cast<std::size_t>(a)], keep[static_cast<std::size_t>(b)]);
    }
    innovation_covariance(P, Hk, Rk, PHtk, Sk);
    const auto u = kfw::update(x, P, yk, Sk, PHtk, UpdateRules{}, Hk, Rk);
    for (Eigen::Index a = 0; a < mk; ++a) {
      const Pending& q = batch[use[static_cast<std::size_t>(keep[static_cast<std::size_t>(a)])]];
      if (!u.updated()) {
        if (auto st = ctx.skip(q.c, q.row, ctx.s_not_pd(q.c, Sk, false)); !st) return st;
        continue;
      }
      ChannelSeries& series = ctx.r.chans[q.c];
      ++series.updates;
      series.nis[q.row] = yk(a) * yk(a) / Sk(a, a);
      series.log_det_s[q.row] = std::log(Sk(a, a));
      for (Eigen::Index i = 0; i < n; ++i)
        series.K[static_cast<std::size_t>(i)][q.row] = u.K(i, a);
    }
    ctx.wrap_states(x);
    return ctx.check_estimate(k, x, P);
  }

  // A channel of several components. Not inlined: its fixed-capacity matrices would give the
  // step loop a 2 KiB frame, and the scalar path's run was 8 % slower for it
  // (BM_HelicopterModelRun).
  // False when the update could not be applied (then `why` says why).
  [[gnu::noinline]] bool update_vector(std::size_t c, std::size_t k, const ModelEval::Channel& ch,
                                       const ChannelSpec& cs) {
    const int m = cs.size();
    typename D::MeasJac H(m, n);
    H = ch.H;
    typename D::Cross PHt(n, m);
    typename D::MeasCov S(m, m);
    innovation_covariance(P, H, ch.R, PHt, S);
    typename D::Meas y(m);
    for (int j = 0; j < m; ++j) {
      const double zhat = cs.linear ? H.row(j).dot(x.transpose()) : ch.hx(j);
      if (!std::isfinite(zhat)) return zhat_skipped(c, j);
      y(j) = ctx.z_buf[static_cast<std::size_t>(j)] - zhat;
    }
    const auto u = kfw::update(x, P, y, S, PHt, ctx.rules(c), H, ch.R);
    ctx.record_update(c, k, u);
    if (u.status != UpdateStatus::kSkipped) return true;
    return s_skipped(c, S);
  }

  // A scalar channel: the update without factorisation. False when it could not be applied.
  bool update_scalar(std::size_t c, std::size_t k, const ModelEval::Channel& ch, bool linear) {
    Vec<N> h(n);
    for (Eigen::Index i = 0; i < n; ++i)
      h(i) = ch.H(0, i);
    Vec<N> PHt;
    PHt.noalias() = P * h;
    const double S = h.dot(PHt) + ch.R(0, 0);
    const double zhat = linear ? h.dot(x) : ch.hx(0);
    if (!std::isfinite(zhat)) [[unlikely]]
      return zhat_skipped(c, 0);
    const auto u = kfw::update(x, P, ctx.z_buf[0] - zhat, S, PHt, ctx.rules(c));
    ctx.record_update(c, k, u);
    if (u.status != UpdateStatus::kSkipped) [[likely]]
      return true;
    return s_skipped(c, MatX::Constant(1, 1, S));
  }

  // An update not applied: why, kept out of the step loop. Both return false.
  [[gnu::cold, gnu::noinline]] bool zhat_skipped(std::size_t c, Eigen::Index j) {
    why = ctx.zhat_not_finite(c, j, false);
    return false;
  }
  [[gnu::cold, gnu::noinline]] bool s_skipped(std::size_t c, const MatX& S) {
    why = ctx.s_not_pd(c, S, false);
    return false;
  }
};

template <int N>
struct UnscentedFilter {
  static constexpr int kSig = N == Eigen::Dynamic ? Eigen::Dynamic : 2 * N + 1;
  using Sig = Eigen::Matrix<double, N, kSig>;
  using D = Dims<N>;
  Context& ctx;
  Vec<N> x;
  Covariance<N> P;
  Eigen::Index n = x.size();
  Eigen::Index ns = 2 * n + 1;
  UkfWeights w = UkfWeights::scaled(n, ctx.options.alpha, ctx.options.beta, ctx.options.kappa);
  bool nonlinear = ctx.spec.nonlinear_process();
  bool q_state = ctx.spec.process_noise_at_state();
  Sig X{n, ns}, Y{n, ns};
  Vec<N> xs{n};           // one sigma point, for the evaluator
  std::vector<MatX> Z{};  // per channel: h of the sigma points

  Status lost(std::size_t k) const {
    return ctx.fail(k, "the covariance P lost definiteness (no sigma points); the run stops here");
  }

  // Y_j = f(X_j, u) (or F X_j + B u); x⁻ = Σ Wm Y_j; P⁻ = Σ Wc (Y_j − x⁻)(Y_j − x⁻)ᵀ + Q.
  Status predict(std::size_t k) {
    ModelEval& ev = ctx.ev;
    if (q_state) {
      ev.set_state(x.data());
      ev.process_noise();
    }
    if (ev.process_noise_varies()) {
      if (auto st = ctx.check_process_noise(k); !st) return st;
    }
    if (!sigma_points<N>(x, P, w, X)) return lost(k);
    for (Eigen::Index j = 0; j < ns; ++j) {
      if (nonlinear) {
        xs = X.col(j);
        ev.set_state(xs.data());
        ev.process_f();
        Y.col(j) = ev.fx;
      } else {
        Y.col(j).noalias() = ev.F * X.col(j);
        for (Eigen::Index i = 0; i < ev.B.cols(); ++i)
          Y.col(j) += ev.B.col(i) * ctx.u_held[static_cast<std::size_t>(i)];
      }
    }
    unscented_predict(Y, w, ctx.state_angle, ev.Q, x, P);
    return ctx.check_estimate(k, x, P);
  }

  // Channel c at row k: Z_j = h(X_j) (or H X_j), ẑ, S and C = P_xz from them, y = z − ẑ; then the
  // update, after which angle states are wrapped.
  Status update(std::size_t c, std::size_t k) {
    const ChannelSpec& cs = ctx.spec.channels[c];
    ModelEval& ev = ctx.ev;
    ModelEval::Channel& ch = ev.channel(c);
    if (ch.R_at_state) {
      ev.set_state(x.data());
      ev.channel_noise(c);
    }
    if (ch.R_varies) {
      if (auto st = ctx.check_channel_noise(c, k); !st) return st;
    }
    if (!sigma_points<N>(x, P, w, X)) return lost(k);
    MatX& Zc = Z[c];
    for (Eigen::Index j = 0; j < ns; ++j) {
      if (cs.linear) {
        Zc.col(j).noalias() = ch.H * X.col(j);
      } else {
        xs = X.col(j);
        ev.set_state(xs.data());
        ev.channel_h(c);
        Zc.col(j) = ch.hx;
      }
    }
    const auto um = unscented_measurement<N, Eigen::Dynamic, kM>(X, x, Zc, w, ctx.state_angle,
                                                                 ctx.role_angle[c], ch.R);
    typename D::Meas y(cs.size());
    for (Eigen::Index j = 0; j < y.size(); ++j) {
      if (!std::isfinite(um.zhat(j))) return ctx.skip(c, k, ctx.zhat_not_finite(c, j, true));
      y(j) = ctx.z_buf[static_cast<std::size_t>(j)] - um.zhat(j);
    }
    const auto u = kfw::update(x, P, y, um.S, um.C, ctx.rules(c));
    ctx.record_update(c, k, u);
    if (u.status == UpdateStatus::kSkipped) return ctx.skip(c, k, ctx.s_not_pd(c, um.S, true));
    if (!u.updated()) return Ok{};
    ctx.wrap_states(x);
    return ctx.check_estimate(k, x, P);
  }
};

}  // namespace kfw::model::detail
