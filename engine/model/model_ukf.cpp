// The run of one unscented Kalman filter (model_filters.h: UnscentedFilter) over a dataset.
#include "model/model_filters.h"

namespace kfw::model::detail {

template <int N>
Status run_ukf(Context& ctx, Vec<N> x, Covariance<N> P) {
  UnscentedFilter<N> f{ctx, std::move(x), std::move(P)};
  for (const auto& cs : ctx.spec.channels)
    f.Z.push_back(MatX::Zero(cs.size(), f.ns));
  return run_steps(ctx, f);
}

KFW_MODEL_FILTER_SIZES(run_ukf)

}  // namespace kfw::model::detail
