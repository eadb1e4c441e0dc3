// Speed of the seed 004 workbench loop: a 3-minute simulation, the EKF over it per scheme, and the
// two together through the scenario, as the GUI re-runs them on every simulator slider move.
#include <benchmark/benchmark.h>

#include "core/scenario.h"
#include "document/preset.h"
#include "oracles/underwater/underwater_ekf.h"
#include "oracles/underwater/underwater_params.h"
#include "oracles/underwater/underwater_sim.h"
#include "oracles/underwater/underwater_stats.h"

namespace {

kfw::underwater::SimParams default_run() {
  kfw::underwater::SimParams p;  // Table 3 clocks, Table 9/10 noise
  p.sigma_t_s = 0.001;
  p.sigma_corr_m = 0.2;
  p.outliers = 276;
  return p;
}

// The 3-minute asynchronous simulation (~35 000 rows, 26 columns).
void BM_Simulate3Min(benchmark::State& state) {
  const auto p = default_run();
  for (auto _ : state) {
    auto d = kfw::underwater::simulate(p);
    benchmark::DoNotOptimize(d.columns.data());
  }
}
BENCHMARK(BM_Simulate3Min)->Unit(benchmark::kMillisecond);

// The EKF over that log; arg = scheme (0 AS, 1 SC, 2 SI).
void BM_Ekf3Min(benchmark::State& state) {
  using namespace kfw::underwater;
  const auto d = simulate(default_run());
  FilterParams f;
  f.scheme = static_cast<Scheme>(state.range(0));
  for (auto _ : state) {
    auto r = run_ekf(d, f);
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d.rows()));
}
BENCHMARK(BM_Ekf3Min)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The covariance statistics of the simulated errors.
void BM_Stats3Min(benchmark::State& state) {
  const auto d = kfw::underwater::simulate(default_run());
  for (auto _ : state) {
    auto s = kfw::underwater::error_stats(d);
    benchmark::DoNotOptimize(s);
  }
}
BENCHMARK(BM_Stats3Min)->Unit(benchmark::kMillisecond);

// What a simulator slider cost in the GUI with the hand-written EKF (tests/oracles/underwater,
// the built-in scenario's until issue 30): simulate + filter + error statistics.
void BM_SimulateAndRun3Min(benchmark::State& state) {
  auto p = kfw::load_preset(KFW_SOURCE_DIR "/presets/underwater.json");
  if (!p) {
    state.SkipWithError(p.error().c_str());
    return;
  }
  for (auto _ : state) {
    auto d = kfw::underwater::simulate(kfw::underwater::sim_params(p->values));
    auto r = kfw::underwater::run_ekf(d, kfw::underwater::filter_params(p->values));
    auto s = kfw::underwater::error_stats(d);
    benchmark::DoNotOptimize(r);
    benchmark::DoNotOptimize(s);
  }
}
BENCHMARK(BM_SimulateAndRun3Min)->Unit(benchmark::kMillisecond);

// The same run as presets/underwater.json (the model file that replaced the built-in, SC): what a
// filter slider costs in the GUI before drawing; the built-in's BM_Ekf3Min/1 is the reference.
void BM_ModelFileRun3Min(benchmark::State& state) {
  auto p = kfw::load_preset(KFW_SOURCE_DIR "/presets/underwater.json");
  if (!p) {
    state.SkipWithError(p.error().c_str());
    return;
  }
  const auto& sc = *p->instance;
  auto d = sc.simulate(p->values);
  if (!d) {
    state.SkipWithError(d.error().c_str());
    return;
  }
  for (auto _ : state) {
    auto r = sc.run(*d, p->values);
    if (!r) state.SkipWithError(r.error().c_str());
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d->rows()));
}
BENCHMARK(BM_ModelFileRun3Min)->Unit(benchmark::kMillisecond);

}  // namespace
