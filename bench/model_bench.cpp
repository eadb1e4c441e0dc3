// Speed of model files: the helicopter model against the built-in filter on the same log, a
// 4-state nonlinear model under the EKF and the UKF, the DARE of a 9-state model.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/scenario.h"
#include "data/csv.h"
#include "filter/dare.h"
#include "model/model_scenario.h"
#include "oracles/helicopter/helicopter_oracle.h"
#include "oracles/helicopter/helicopter_sim.h"

namespace {

using namespace kfw;

std::unique_ptr<Scenario> load_model(const std::string& name) {
  const std::string path = KFW_SOURCE_DIR "/presets/models/" + name;
  std::ifstream in(path);
  auto s = make_model_scenario(nlohmann::json::parse(in), path);
  if (!s) throw std::runtime_error(s.error());
  return std::move(*s);
}

// The real log when present (55k rows at 286 Hz), else 55k simulated rows.
const Dataset& helicopter_data() {
  static const Dataset d = [] {
    const std::string log = KFW_SHARED_DIR "/data/broad/10_undisturbed_slow_translation_A.csv";
    if (std::filesystem::exists(log)) {
      if (auto r = read_csv(log)) return *r;
    }
    helicopter::SimParams sp;
    sp.duration_s = 55'000 * sp.Ts_s;
    return helicopter::simulate(sp);
  }();
  return d;
}

void run_scenario(benchmark::State& state, const Scenario& s, const Dataset& d, ParamValues v) {
  for (auto _ : state) {
    auto r = s.run(d, v);
    if (!r) state.SkipWithError(r.error().c_str());
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d.rows()));
}

ParamValues broad_tuning(const Scenario& s) {
  ParamValues v = s.params().defaults();
  v["Q"] = 256;
  v["R"] = 4096;
  v["gamma"] = 0.003;
  return v;
}

// The hand-written helicopter filter (tests/oracles/helicopter, the built-in scenario's until
// issue 30), whole run with the built-in's metrics, on the log: the reference of the next two.
void BM_HelicopterOracleRun(benchmark::State& state) {
  auto s = load_model("helicopter_indirect.json");
  const ParamValues v = broad_tuning(*s);
  const Dataset& d = helicopter_data();
  for (auto _ : state) {
    auto r = helicopter::run_with_metrics(d, v);
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(d.rows()));
}
BENCHMARK(BM_HelicopterOracleRun)->Unit(benchmark::kMillisecond);

// The same filter as a model file (presets/models/helicopter_indirect.json): target ≤ 1.5×.
void BM_HelicopterModelRun(benchmark::State& state) {
  auto s = load_model("helicopter_indirect.json");
  run_scenario(state, *s, helicopter_data(), broad_tuning(*s));
}
BENCHMARK(BM_HelicopterModelRun)->Unit(benchmark::kMillisecond);

// The same linear model under the UKF (sigma points on the real log).
void BM_HelicopterModelUkf(benchmark::State& state) {
  auto s = load_model("helicopter_indirect.json");
  ParamValues v = broad_tuning(*s);
  if (auto st = s->params().apply_assignment("filter=ukf", v); !st) {
    state.SkipWithError(st.error().c_str());
    return;
  }
  run_scenario(state, *s, helicopter_data(), v);
}
BENCHMARK(BM_HelicopterModelUkf)->Unit(benchmark::kMillisecond);

// Range-bearing target (4 states, nonlinear h, 2-D channel), 10 min at 10 Hz; per step:
// EKF target ≤ 2 µs, UKF ≤ 5 µs.
void run_range_bearing(benchmark::State& state, const char* filter) {
  auto s = load_model("range_bearing.json");
  ParamValues v = s->params().defaults();
  v["sim.duration"] = 600;
  auto d = s->simulate(v);
  if (!d) {
    state.SkipWithError(d.error().c_str());
    return;
  }
  if (auto st = s->params().apply_assignment(std::string("filter=") + filter, v); !st) {
    state.SkipWithError(st.error().c_str());
    return;
  }
  run_scenario(state, *s, *d, v);
}
void BM_RangeBearingEkf(benchmark::State& state) {
  run_range_bearing(state, "ekf");
}
void BM_RangeBearingUkf(benchmark::State& state) {
  run_range_bearing(state, "ukf");
}
BENCHMARK(BM_RangeBearingEkf)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RangeBearingUkf)->Unit(benchmark::kMillisecond);

// A 9-state constant-acceleration model in 3-D (position measured): the steady-state gain.
const char* kCa3d = R"json({
  "format": "kfw-preset", "version": 1, "scenario": "model", "title": "CA 3-D",
  "parameters": {
    "q": {"value": 0.1, "min": 1e-6, "max": 1e6, "unit": "m²/s⁵", "scale": "log", "label": "jerk PSD"},
    "r": {"value": 4, "min": 1e-6, "max": 1e6, "unit": "m²", "scale": "log", "label": "R"}
  },
  "model": {
    "version": 1,
    "states": ["x", "vx", "ax", "y", "vy", "ay", "z", "vz", "az"],
    "x0": [0, 0, 0, 0, 0, 0, 0, 0, 0],
    "P0": [100, 10, 1, 100, 10, 1, 100, 10, 1],
    "process": {
      "F": [["1", "dt", "dt^2/2", 0, 0, 0, 0, 0, 0], [0, 1, "dt", 0, 0, 0, 0, 0, 0],
            [0, 0, 1, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, "1", "dt", "dt^2/2", 0, 0, 0], [0, 0, 0, 0, 1, "dt", 0, 0, 0],
            [0, 0, 0, 0, 0, 1, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, "1", "dt", "dt^2/2"], [0, 0, 0, 0, 0, 0, 0, 1, "dt"],
            [0, 0, 0, 0, 0, 0, 0, 0, 1]],
      "Q": [["q*dt^5/20", "q*dt^4/8", "q*dt^3/6", 0, 0, 0, 0, 0, 0],
            ["q*dt^4/8", "q*dt^3/3", "q*dt^2/2", 0, 0, 0, 0, 0, 0],
            ["q*dt^3/6", "q*dt^2/2", "q*dt", 0, 0, 0, 0, 0, 0],
            [0, 0, 0, "q*dt^5/20", "q*dt^4/8", "q*dt^3/6", 0, 0, 0],
            [0, 0, 0, "q*dt^4/8", "q*dt^3/3", "q*dt^2/2", 0, 0, 0],
            [0, 0, 0, "q*dt^3/6", "q*dt^2/2", "q*dt", 0, 0, 0],
            [0, 0, 0, 0, 0, 0, "q*dt^5/20", "q*dt^4/8", "q*dt^3/6"],
            [0, 0, 0, 0, 0, 0, "q*dt^4/8", "q*dt^3/3", "q*dt^2/2"],
            [0, 0, 0, 0, 0, 0, "q*dt^3/6", "q*dt^2/2", "q*dt"]]
    },
    "measurements": {
      "position": {"roles": ["px", "py", "pz"],
                   "H": [[1, 0, 0, 0, 0, 0, 0, 0, 0], [0, 0, 0, 1, 0, 0, 0, 0, 0],
                         [0, 0, 0, 0, 0, 0, 1, 0, 0]],
                   "R": ["r", "r", "r"]}
    }
  }
})json";

// solve_dare alone on the 9-state model (target ≤ 50 µs), and Scenario::gain (which also
// compiles the model's expressions for the run).
void BM_Dare9State(benchmark::State& state) {
  auto s = make_model_scenario(nlohmann::json::parse(kCa3d), "ca3d");
  if (!s) {
    state.SkipWithError(s.error().c_str());
    return;
  }
  auto g = (*s)->gain((*s)->params().defaults());
  if (!g) {
    state.SkipWithError(g.error().c_str());
    return;
  }
  const double T = 0.01, q = 0.1, r = 4;
  MatX F = MatX::Zero(9, 9), Q = MatX::Zero(9, 9), H = MatX::Zero(3, 9);
  for (int a = 0; a < 3; ++a) {
    const int o = 3 * a;
    Mat<3> Fa, Qa;
    Fa << 1, T, T * T / 2, 0, 1, T, 0, 0, 1;
    Qa << std::pow(T, 5) / 20, std::pow(T, 4) / 8, std::pow(T, 3) / 6, std::pow(T, 4) / 8,
        std::pow(T, 3) / 3, T * T / 2, std::pow(T, 3) / 6, T * T / 2, T;
    F.block(o, o, 3, 3) = Fa;
    Q.block(o, o, 3, 3) = q * Qa;
    H(a, o) = 1;
  }
  const MatX R = r * MatX::Identity(3, 3);
  for (auto _ : state) {
    auto ss = solve_dare(F, H, Q, R);
    benchmark::DoNotOptimize(ss);
  }
}
BENCHMARK(BM_Dare9State)->Unit(benchmark::kMicrosecond);

void BM_Gain9State(benchmark::State& state) {
  auto s = make_model_scenario(nlohmann::json::parse(kCa3d), "ca3d");
  if (!s) {
    state.SkipWithError(s.error().c_str());
    return;
  }
  const ParamValues v = (*s)->params().defaults();
  for (auto _ : state) {
    auto g = (*s)->gain(v);
    benchmark::DoNotOptimize(g);
  }
}
BENCHMARK(BM_Gain9State)->Unit(benchmark::kMicrosecond);

}  // namespace
