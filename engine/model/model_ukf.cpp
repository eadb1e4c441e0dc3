// The unscented Kalman filter of any model (filter/ukf.h: scaled sigma points, circular means of
// angle components): the model engine propagates the sigma points through f and h, the library
// forms the moments and applies the one measurement update from C = P_xz. Sigma points are redrawn
// before each channel update.
#include <cmath>

#include "filter/ukf.h"
#include "model/model_filter_detail.h"

namespace kfw::model::detail {

namespace {

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
    return ctx.check_finite(k, x);
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
    return ctx.check_finite(k, x);
  }
};

}  // namespace

template <int N>
Status run_ukf(Context& ctx, Vec<N> x, Covariance<N> P) {
  UnscentedFilter<N> f{ctx, std::move(x), std::move(P)};
  for (const auto& cs : ctx.spec.channels)
    f.Z.push_back(MatX::Zero(cs.size(), f.ns));
  return run_steps(ctx, f);
}

KFW_MODEL_FILTER_SIZES(run_ukf)

}  // namespace kfw::model::detail
