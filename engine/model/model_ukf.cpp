// The unscented Kalman filter with additive noise and scaled sigma points (Julier 2002; Wan &
// van der Merwe 2000): λ = α²(n + κ) − n, W0m = λ/(n + λ), W0c = W0m + 1 − α² + β,
// Wi = 1/(2(n + λ)). Angles (states and channel components) are averaged as the central sigma
// point plus the weighted mean of the wrapped differences from it, and their deviations wrapped,
// so a spread across ±π is handled. Sigma points are redrawn before each channel update.
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "filter/covariance_check.h"
#include "model/model_filter_detail.h"

namespace kfw::model::detail {

namespace {

struct Weights {
  double c = 0.0;  // n + λ
  double m0 = 0.0, c0 = 0.0, i = 0.0;
  double m(Eigen::Index j) const { return j == 0 ? m0 : i; }
  double cw(Eigen::Index j) const { return j == 0 ? c0 : i; }
};

// Lower Cholesky factor of a symmetric A (only its lower triangle read): false if A is not
// positive definite. Plain loops: n ≤ 6 on the fixed-size path, where Eigen's LLT costs more to
// compile than to run.
template <class Mat>
bool cholesky_lower(const Mat& A, Mat& L) {
  const Eigen::Index n = A.rows();
  L.setZero();
  for (Eigen::Index j = 0; j < n; ++j) {
    double d = A(j, j);
    for (Eigen::Index k = 0; k < j; ++k)
      d -= L(j, k) * L(j, k);
    if (!(d > 0.0)) return false;
    const double ljj = std::sqrt(d);
    L(j, j) = ljj;
    for (Eigen::Index i = j + 1; i < n; ++i) {
      double v = A(i, j);
      for (Eigen::Index k = 0; k < j; ++k)
        v -= L(i, k) * L(j, k);
      L(i, j) = v / ljj;
    }
  }
  return true;
}

// The symmetric square root of a positive semi-definite A (a singular P, e.g. a state the noise
// does not drive); false if A has an eigenvalue below −1e-9 of its largest. Dynamic size: a rare
// path, compiled once.
bool symmetric_sqrt(const MatX& A, MatX& L) {
  Eigen::SelfAdjointEigenSolver<MatX> es(A);
  if (es.info() != Eigen::Success) return false;
  const double scale = es.eigenvalues().cwiseAbs().maxCoeff();
  if (es.eigenvalues().minCoeff() < -1e-9 * scale) return false;
  L = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() *
      es.eigenvectors().transpose();
  return true;
}

// The 2n + 1 sigma points of N(x, P): x and x ± the columns of √((n + λ) P). A P that lost
// definiteness beyond rounding returns false.
template <int N, class Sig>
bool sigma_points(const typename Types<N>::VecN& x, const typename Types<N>::MatN& P,
                  const Weights& w, Sig& X) {
  using MatN = typename Types<N>::MatN;
  const Eigen::Index n = x.size();
  const MatN A = w.c * P;
  MatN L(n, n);
  if (!cholesky_lower(A, L)) {
    MatX Ls;
    if (!symmetric_sqrt(A, Ls)) return false;
    L = Ls;
  }
  X.col(0) = x;
  for (Eigen::Index j = 0; j < n; ++j) {
    X.col(1 + j) = x + L.col(j);
    X.col(1 + n + j) = x - L.col(j);
  }
  return true;
}

// Weighted mean of the columns of Y, angle rows relative to the central column.
template <class Sig, class Out>
void sigma_mean(const Sig& Y, const Weights& w, const std::vector<Angle>& angle, Out& mean) {
  for (Eigen::Index r = 0; r < Y.rows(); ++r) {
    const Angle a = angle[static_cast<std::size_t>(r)];
    if (a == Angle::kNone) {
      double s = 0.0;
      for (Eigen::Index j = 0; j < Y.cols(); ++j)
        s += w.m(j) * Y(r, j);
      mean(r) = s;
    } else {
      const double ref = Y(r, 0);
      double s = 0.0;
      for (Eigen::Index j = 0; j < Y.cols(); ++j)
        s += w.m(j) * wrap(Y(r, j) - ref, a);
      mean(r) = wrap(ref + s, a);
    }
  }
}

// Column j of Y minus the mean, angle rows wrapped.
template <class Sig, class Mean, class Out>
void deviation(const Sig& Y, Eigen::Index j, const Mean& mean, const std::vector<Angle>& angle,
               Out& d) {
  for (Eigen::Index r = 0; r < Y.rows(); ++r)
    d(r) = wrap(Y(r, j) - mean(r), angle[static_cast<std::size_t>(r)]);
}

}  // namespace

template <int N>
Status run_ukf(Context& ctx, typename Types<N>::VecN x, typename Types<N>::MatN P) {
  using T = Types<N>;
  constexpr int kSig = N == Eigen::Dynamic ? Eigen::Dynamic : 2 * N + 1;
  using Sig = Eigen::Matrix<double, N, kSig>;
  const ModelSpec& spec = ctx.spec;
  ModelEval& ev = ctx.ev;
  const auto& t = *ctx.data.t;
  const Eigen::Index n = x.size();
  const Eigen::Index ns = 2 * n + 1;
  const auto& o = ctx.options;
  const double lambda =
      o.alpha * o.alpha * (static_cast<double>(n) + o.kappa) - static_cast<double>(n);
  Weights w;
  w.c = static_cast<double>(n) + lambda;
  w.m0 = lambda / w.c;
  w.c0 = w.m0 + 1.0 - o.alpha * o.alpha + o.beta;
  w.i = 0.5 / w.c;

  const bool nonlinear = spec.process.form == ProcessForm::kNonlinear;
  const bool q_state = spec.process.Q.dep() == Dep::kState;
  const auto nu = static_cast<Eigen::Index>(ctx.u_held.size());
  std::vector<Angle> state_angle;
  bool any_angle = false;
  for (const auto& s : spec.states) {
    state_angle.push_back(s.angle);
    any_angle = any_angle || s.angle != Angle::kNone;
  }
  std::vector<std::vector<Angle>> role_angle(spec.channels.size());
  std::vector<MatX> Z(spec.channels.size());
  for (std::size_t c = 0; c < spec.channels.size(); ++c) {
    for (const auto& r : spec.channels[c].roles)
      role_angle[c].push_back(r.angle);
    Z[c].setZero(spec.channels[c].size(), ns);
  }
  Sig X(n, ns), Y(n, ns);
  typename T::VecN d(n), xp(n);
  auto lost = [&](std::size_t k) {
    return ctx.fail(k, "the covariance P lost definiteness (no sigma points); the run stops here");
  };

  for (std::size_t k = 0; k < ctx.data.rows; ++k) {
    if (k > 0) {
      if (auto st = ev.set_dt(t[k] - t[k - 1]); !st) return ctx.fail(k, st.error());
      ev.set_time(t[k - 1]);
      ev.set_inputs(ctx.u_held.data());
      ev.process_step();
      if (q_state) {
        ev.set_state(x.data());
        ev.process_noise();
      }
      if (ev.process_noise_varies()) {
        if (auto st = ctx.check_noise(k, ev.Q, "model.process.Q"); !st) return st;
      }
      if (!sigma_points<N>(x, P, w, X)) return lost(k);
      // Y_j = f(X_j, u) (or F X_j + B u); x⁻ = Σ Wm Y_j; P⁻ = Σ Wc (Y_j − x⁻)(Y_j − x⁻)ᵀ + Q.
      for (Eigen::Index j = 0; j < ns; ++j) {
        if (nonlinear) {
          xp = X.col(j);
          ev.set_state(xp.data());
          ev.process_f();
          Y.col(j) = ev.fx;
        } else {
          Y.col(j).noalias() = ev.F * X.col(j);
          for (Eigen::Index i = 0; i < nu; ++i)
            Y.col(j) += ev.B.col(i) * ctx.u_held[static_cast<std::size_t>(i)];
        }
      }
      sigma_mean(Y, w, state_angle, x);
      P = ev.Q;
      for (Eigen::Index j = 0; j < ns; ++j) {
        deviation(Y, j, x, state_angle, d);
        P.noalias() += w.cw(j) * d * d.transpose();
      }
      P = 0.5 * (P + P.transpose()).eval();
      if (auto st = ctx.check_finite(k, x); !st) return st;
    }
    ctx.hold_inputs(k);
    bool row_set = false;
    for (std::size_t c = 0; c < spec.channels.size(); ++c) {
      if (!ctx.channel_ready(c, k)) continue;
      const ChannelSpec& cs = spec.channels[c];
      ModelEval::Channel& ch = ev.channel(c);
      ChannelSeries& out = ctx.r.chans[c];
      const Eigen::Index m = cs.size();
      if (!row_set) {
        ev.set_time(t[k]);
        ev.set_inputs(ctx.u_held.data());
        row_set = true;
      }
      ev.channel_step(c);
      if (cs.R.dep() == Dep::kState) {
        ev.set_state(x.data());
        ev.channel_noise(c);
      }
      if (ch.R_varies) {
        if (auto st = ctx.check_noise(k, ch.R, cs.R.key); !st) return st;
      }
      if (!sigma_points<N>(x, P, w, X)) return lost(k);
      MatX& Zc = Z[c];
      for (Eigen::Index j = 0; j < ns; ++j) {
        if (cs.linear) {
          Zc.col(j).noalias() = ch.H * X.col(j);
        } else {
          xp = X.col(j);
          ev.set_state(xp.data());
          ev.channel_h(c);
          Zc.col(j) = ch.hx;
        }
      }
      // ẑ = Σ Wm Z_j, S = Σ Wc (Z_j − ẑ)(·)ᵀ + R, C = Σ Wc (X_j − x)(Z_j − ẑ)ᵀ, K = C S⁻¹.
      typename T::VecM zhat(m), dz(m), y(m);
      sigma_mean(Zc, w, role_angle[c], zhat);
      typename T::MatM S = ch.R;
      typename T::MatNM C(n, m);
      C.setZero();
      for (Eigen::Index j = 0; j < ns; ++j) {
        deviation(Zc, j, zhat, role_angle[c], dz);
        deviation(X, j, x, state_angle, d);
        S.noalias() += w.cw(j) * dz * dz.transpose();
        C.noalias() += w.cw(j) * d * dz.transpose();
      }
      for (Eigen::Index j = 0; j < m; ++j)
        y(j) = wrap(ctx.z_buf[static_cast<std::size_t>(j)] - zhat(j),
                    role_angle[c][static_cast<std::size_t>(j)]);
      Eigen::LLT<typename T::MatM> llt(S);
      if (llt.info() != Eigen::Success || !S.allFinite()) {
        ++out.skipped;
        continue;
      }
      const double nis = y.dot(llt.solve(y));
      if (ch.gate_nis > 0.0 && nis > ch.gate_nis) {
        ++out.gated;
        ctx.record_update(c, k, y, S, kNoSample, kNoSample, typename T::MatNM());
        continue;
      }
      double log_det = 0.0;
      for (Eigen::Index j = 0; j < m; ++j)
        log_det += 2.0 * std::log(llt.matrixLLT()(j, j));
      const typename T::MatNM K = llt.solve(C.transpose()).transpose();
      x.noalias() += K * y;
      P.noalias() -= K * S * K.transpose();
      P = 0.5 * (P + P.transpose()).eval();
      debug_check_covariance(P, "a UKF update");
      if (any_angle) {
        for (Eigen::Index i = 0; i < n; ++i)
          x(i) = wrap(x(i), state_angle[static_cast<std::size_t>(i)]);
      }
      ++out.updates;
      ctx.record_update(c, k, y, S, nis, log_det, K);
      if (auto st = ctx.check_finite(k, x); !st) return st;
    }
    ctx.record_state(k, x, P);
    if ((k & 0xFFF) == 0xFFF && ctx.control.cancelled()) return Error{"cancelled"};
  }
  return Ok{};
}

#define KFW_MODEL_UKF(N) \
  template Status run_ukf<N>(Context&, typename Types<N>::VecN, typename Types<N>::MatN);
KFW_MODEL_UKF(1)
KFW_MODEL_UKF(2)
KFW_MODEL_UKF(3)
KFW_MODEL_UKF(4)
KFW_MODEL_UKF(5)
KFW_MODEL_UKF(6)
KFW_MODEL_UKF(Eigen::Dynamic)
#undef KFW_MODEL_UKF

}  // namespace kfw::model::detail
