// Speed of the 2-state indirect KF: the raw step and a whole-dataset re-filter.
#include <benchmark/benchmark.h>

#include "filter/kalman_filter.h"
#include "oracles/helicopter/helicopter_sim.h"
#include "oracles/helicopter/indirect_kf.h"

namespace {

// One predict + update of the 2-state filter (target: >= 20 million steps/s).
void BM_IndirectKfStep(benchmark::State& state) {
  using namespace kfw;
  Gaussian<2> g;
  g.x << 0.0, 0.0;
  g.P << 100.0, 0.0, 0.0, 4.0;
  const double Ts = 0.02;
  Mat<2> F;
  F << 1.0, -Ts, 0.0, 1.0;
  Covariance<2> Q;
  Q << Ts * Ts * 67.0, 0.0, 0.0, 0.0;
  const Mat<1, 2> H(1.0, 0.0);
  double z = 0.1;
  for (auto _ : state) {
    g = predict(g, F, Vec<2>(Ts * 0.5, 0.0), Q);
    const auto u = update_scalar(g, z, H, 1.96);
    g = u.post;
    z = -z;
    benchmark::DoNotOptimize(g);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_IndirectKfStep);

// Re-filtering a 1-million-sample dataset with every per-step output stored (target <= 50 ms).
void BM_Refilter1M(benchmark::State& state) {
  using namespace kfw::helicopter;
  SimParams sp;
  sp.duration_s = 1e6 * sp.Ts_s - sp.Ts_s / 2;
  const auto d = simulate(sp);
  FilterParams fp;
  fp.N_omega = 67.24;
  fp.N_theta = 1.96;
  for (auto _ : state) {
    auto r = run_indirect_kf(d.col("t"), d.col("gyro"), d.col("angle"), fp);
    benchmark::DoNotOptimize(r.theta.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d.rows()));
}
BENCHMARK(BM_Refilter1M)->Unit(benchmark::kMillisecond);

}  // namespace
