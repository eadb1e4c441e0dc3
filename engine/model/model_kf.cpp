// The run of one Kalman or extended Kalman filter (model_filters.h: KalmanFilter) over a dataset.
#include "model/model_filters.h"

namespace kfw::model::detail {

template <int N>
Status run_kf(Context& ctx, Vec<N> x, Covariance<N> P) {
  KalmanFilter<N> f{ctx, std::move(x), std::move(P)};
  return run_steps(ctx, f);
}

KFW_MODEL_FILTER_SIZES(run_kf)

}  // namespace kfw::model::detail
