// Speed of the seed 003 ball tracker (α-β and KF steps) and of the closed-loop simulation.
#include <benchmark/benchmark.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "core/scenario.h"
#include "model/model_scenario.h"
#include "oracles/ballbeam/ball_tracker.h"
#include "oracles/ballbeam/ballbeam_loop.h"

namespace {

using namespace kfw;
using namespace kfw::ballbeam;

BallTracker tracker(FilterKind kind) {
  TrackerParams p;
  p.Q = 0.5013;
  p.kind = kind;
  return *BallTracker::make(p);
}

// One predict + update of the tracker, every 10th sample missing.
void TrackerStep(benchmark::State& state, FilterKind kind) {
  const BallTracker t = tracker(kind);
  Gaussian<2> g = t.initial(0.0);
  double z = 1e-3;
  int k = 0;
  for (auto _ : state) {
    g = t.update(t.predict(g, 0.1), z, ++k % 10 == 0).out;
    z = -z;
    benchmark::DoNotOptimize(g);
  }
  state.SetItemsProcessed(state.iterations());
}
void BM_AlphaBetaStep(benchmark::State& state) {
  TrackerStep(state, FilterKind::kSteady);
}
void BM_KalmanStep(benchmark::State& state) {
  TrackerStep(state, FilterKind::kKalman);
}
BENCHMARK(BM_AlphaBetaStep);
BENCHMARK(BM_KalmanStep);

// The bare α-β recursion with the fixed gain (no covariance): the paper's real-time form.
void BM_AlphaBetaBare(benchmark::State& state) {
  const double Ts = 0.01, alpha = 0.2335, beta = 0.0310;
  double x = 0.0, v = 0.0, z = 1e-3;
  for (auto _ : state) {
    x += Ts * v;
    const double r = z - x;
    x += alpha * r;
    v += beta / Ts * r;
    z = -z;
    benchmark::DoNotOptimize(x);
    benchmark::DoNotOptimize(v);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_AlphaBetaBare);

// One closed-loop run of the preset (15 s at 10 ms, RK4 plant, tracker, PID/PD).
void BM_ClosedLoop15s(benchmark::State& state) {
  LoopParams p;
  const BallTracker t = tracker(FilterKind::kSteady);
  const Disturbances d = make_disturbances(loop_steps(p), p);
  for (auto _ : state) {
    auto tr = run_closed_loop(p, t, d, LoopOptions{});
    benchmark::DoNotOptimize(tr.x_true.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(loop_steps(p)));
}
BENCHMARK(BM_ClosedLoop15s)->Unit(benchmark::kMicrosecond);

std::unique_ptr<Scenario> model_file() {
  std::ifstream in(KFW_SOURCE_DIR "/presets/ballbeam.json");
  auto s = make_model_scenario(nlohmann::json::parse(in), "ballbeam.json");
  if (!s) throw std::runtime_error(s.error());
  return std::move(*s);
}

// Issue 30: the model file's closed loop. Arg 0: one loop of 15 s (Scenario::simulate: world,
// sensors, filter, controller — the work of BM_ClosedLoop15s; target ≤ 2× per step). Arg 1: a
// slider move, Scenario::run with the noise-free twin and every metric.
void BM_ModelLoop15s(benchmark::State& state) {
  auto s = model_file();
  const ParamValues v = s->params().defaults();
  const Dataset d;
  for (auto _ : state) {
    if (state.range(0) == 0) {
      auto r = s->simulate(v);
      if (!r) state.SkipWithError(r.error().c_str());
      benchmark::DoNotOptimize(r);
    } else {
      auto r = s->run(d, v);
      if (!r) state.SkipWithError(r.error().c_str());
      benchmark::DoNotOptimize(r);
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(1501));
}
BENCHMARK(BM_ModelLoop15s)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
