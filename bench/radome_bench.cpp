// Speed of the radome IMM (issue 3): one 49-mode step (target <= 20 µs; FilterPy's IMMEstimator
// with 49 modes of 9 states takes ~21 ms on this machine) and the whole default run (<= 100 ms).
#include <benchmark/benchmark.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "core/scenario.h"
#include "model/model_scenario.h"
#include "scenarios/radome/radome_imm.h"
#include "scenarios/radome/radome_sim.h"

namespace {

using namespace kfw;

std::vector<radome::Sample> samples() {
  auto d = radome::simulate(radome::SimParams{});
  std::vector<radome::Sample> out;
  for (std::size_t k = 0; k < d->rows(); ++k) {
    radome::Sample s;
    s.t_s = d->col("t")[k];
    s.range_m = d->col("range_m")[k];
    s.psi_rad = d->col("psi_rad")[k];
    s.theta_rad = d->col("theta_rad")[k];
    s.psi_a_rad = d->col("psi_a_rad")[k];
    s.theta_a_rad = d->col("theta_a_rad")[k];
    out.push_back(s);
  }
  return out;
}

// One IMM cycle (mixing, 49 mode-matched filters, probabilities, combination, renewal).
void BM_RadomeImmStep(benchmark::State& state) {
  const auto s = samples();
  radome::FilterParams p;
  p.n_psi = p.n_theta = static_cast<int>(state.range(0));
  p.structure = state.range(1) ? radome::Structure::kFull : radome::Structure::kAxisBlocks;
  p.Kp = 0.0;
  auto make = [&] {
    auto f = radome::RadomeImm::create(p, 0.05);
    f->initialize(s[0]);
    return std::move(*f);
  };
  radome::RadomeImm imm = make();
  std::size_t k = 1;
  for (auto _ : state) {
    if (k == s.size()) {
      state.PauseTiming();
      imm = make();
      k = 1;
      state.ResumeTiming();
    }
    auto o = imm.step(s[k], 0.05);
    benchmark::DoNotOptimize(o);
    ++k;
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(std::to_string(imm.modes()) + " modes, " +
                 (state.range(1) ? "full 9-state" : "axis blocks"));
}
BENCHMARK(BM_RadomeImmStep)
    ->Args({7, 0})
    ->Args({7, 1})
    ->Args({3, 0})
    ->Args({15, 0})
    ->Unit(benchmark::kMicrosecond);

// The whole default run as `kfw-cli run presets/radome.json` does it (1201 steps, all outputs).
void BM_RadomeDefaultRun(benchmark::State& state) {
  auto sc = make_scenario("radome");
  ParamValues v = (*sc)->params().defaults();
  v["imm.structure"] = static_cast<double>(state.range(0));
  const auto d = (*sc)->simulate(v);
  for (auto _ : state) {
    auto r = (*sc)->run(*d, v);
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d->rows()));
}
BENCHMARK(BM_RadomeDefaultRun)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The same run from seed 001's model file (presets/radome.json, issue 28) on the
// built-in's data: the target is 1.5x BM_RadomeDefaultRun (axis 0, full 1).
void BM_RadomeModelRun(benchmark::State& state) {
  std::ifstream in(KFW_SOURCE_DIR "/presets/radome.json");
  auto s = make_model_scenario(nlohmann::json::parse(in), "radome.json");
  if (!s) {
    state.SkipWithError(s.error().c_str());
    return;
  }
  auto builtin = make_scenario("radome");
  ParamValues v = (*s)->params().defaults();
  v["imm.structure"] = static_cast<double>(state.range(0));
  const auto d = (*builtin)->simulate((*builtin)->params().defaults());
  for (auto _ : state) {
    auto r = (*s)->run(*d, v);
    if (!r) state.SkipWithError(r.error().c_str());
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d->rows()));
}
BENCHMARK(BM_RadomeModelRun)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
