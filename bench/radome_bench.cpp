// Speed of the radome IMM (issue 3): one 49-mode step (target <= 20 µs; FilterPy's IMMEstimator
// with 49 modes of 9 states takes ~21 ms on this machine) and the whole default run (<= 100 ms).
#include <benchmark/benchmark.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "core/scenario.h"
#include "model/model_scenario.h"
#include "oracles/radome/radome_imm.h"
#include "oracles/radome/radome_metrics.h"
#include "oracles/radome/radome_params.h"
#include "oracles/radome/radome_sim.h"

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

std::unique_ptr<Scenario> radome_file() {
  std::ifstream in(KFW_SOURCE_DIR "/presets/radome.json");
  auto s = make_model_scenario(nlohmann::json::parse(in), "radome.json");
  if (!s) throw std::runtime_error(s.error());
  return std::move(*s);
}

// The hand-written IMM (tests/oracles/radome, the built-in scenario's until issue 30) over the
// default run with the built-in's metrics (1201 steps): the reference of BM_RadomeModelRun.
void BM_RadomeOracleRun(benchmark::State& state) {
  const auto s = radome_file();
  ParamValues v = s->params().defaults();
  v["imm.structure"] = static_cast<double>(state.range(0));
  const Dataset d = radome::simulate(radome::sim_params(v)).value();
  const radome::FilterParams p = radome::filter_params(v);
  for (auto _ : state) {
    auto r = radome::run_radome_with_metrics(d, p);
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d.rows()));
}
BENCHMARK(BM_RadomeOracleRun)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The same run from seed 001's model file (presets/radome.json, issue 28) on the oracle's data
// (the file's world simulates the same to 1e-12): the target is 1.5x BM_RadomeOracleRun.
void BM_RadomeModelRun(benchmark::State& state) {
  const auto s = radome_file();
  ParamValues v = s->params().defaults();
  v["imm.structure"] = static_cast<double>(state.range(0));
  const Dataset d = radome::simulate(radome::sim_params(v)).value();
  for (auto _ : state) {
    auto r = s->run(d, v);
    if (!r) state.SkipWithError(r.error().c_str());
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d.rows()));
}
BENCHMARK(BM_RadomeModelRun)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
