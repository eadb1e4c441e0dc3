// The run of one Kalman or extended Kalman filter (model_filters.h: KalmanFilter) over a dataset,
// and of the steady-state filter (filter = steady, issue 30): the KF's prediction, and an update
// with the fixed DARE gain whose covariance is carried in Joseph form, exact for any gain, so S,
// the NIS and the ±2σ bands stay honest while samples are missing (seed 003's α-β filter).
#include "model/model_filters.h"

namespace kfw::model::detail {

template <int N>
Status run_kf(Context& ctx, Vec<N> x, Covariance<N> P) {
  KalmanFilter<N> f{ctx, std::move(x), std::move(P)};
  return run_steps(ctx, f);
}

KFW_MODEL_FILTER_SIZES(run_kf)

namespace {

template <int N>
struct SteadyFilter : KalmanFilter<N> {
  using D = Dims<N>;

  // x⁺ = x⁻ + K y, P⁺ = (I − K H) P⁻ (I − K H)ᵀ + K R Kᵀ; y, S = H P⁻ Hᵀ + R and the NIS
  // recorded as the KF's. No gate and no skip: the gain does not depend on S.
  Status update(std::size_t c, std::size_t k) {
    Context& cx = this->ctx;
    const ModelEval::Channel& ch = cx.ev.channel(c);
    const auto m = static_cast<Eigen::Index>(cx.spec.channels[c].size());
    const Eigen::Index dim = this->n;
    MeasurementUpdate<N, Eigen::Dynamic, kM> u;
    typename D::MeasJac H(m, dim);
    H = ch.H;
    typename D::Cross PHt(dim, m);
    typename D::MeasCov S(m, m);
    innovation_covariance(this->P, H, ch.R, PHt, S);
    u.y.resize(m);
    for (Eigen::Index j = 0; j < m; ++j) {
      u.y(j) = wrap(cx.z_buf[static_cast<std::size_t>(j)] - H.row(j).dot(this->x.transpose()),
                    cx.role_angle[c][static_cast<std::size_t>(j)]);
    }
    u.S = S;
    u.K = cx.steady_K;
    Eigen::LLT<typename D::MeasCov> llt(S);
    if (llt.info() == Eigen::Success) {
      u.nis = u.y.dot(llt.solve(u.y));
      double log_det = 0.0;
      for (Eigen::Index j = 0; j < m; ++j)
        log_det += 2.0 * std::log(llt.matrixLLT()(j, j));
      u.log_det_S = log_det;
    }
    this->x += u.K * u.y;
    Covariance<N> IKH = Covariance<N>::Identity(dim, dim);
    IKH.noalias() -= u.K * H;
    Covariance<N> Pj = IKH * this->P * IKH.transpose();
    Pj.noalias() += u.K * ch.R * u.K.transpose();
    this->P = 0.5 * (Pj + Pj.transpose());
    u.status = UpdateStatus::kUpdated;
    cx.record_update(c, k, u);
    cx.wrap_states(this->x);
    return cx.check_estimate(k, this->x, this->P);
  }
};

}  // namespace

template <int N>
Status run_steady(Context& ctx, Vec<N> x, Covariance<N> P) {
  SteadyFilter<N> f{{ctx, std::move(x), std::move(P)}};
  return run_steps(ctx, f);
}

KFW_MODEL_FILTER_SIZES(run_steady)

}  // namespace kfw::model::detail
