// Speed of loading a CSV (docs/speed.md "Loading a CSV"): the 55 k-row real log (target < 30 ms)
// and a generated 1 M-row, 4-column file (target < 300 ms), each from disk to a scenario's dataset.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "core/scenario.h"
#include "document/preset.h"
#include "document/workspace.h"

namespace {

// A 1 M-row log like kfw's own output: t, gyro, angle, truth at full precision (about 85 MB,
// the size of the file in issue 13).
const std::string& million_row_file() {
  static const std::string path = [] {
    const auto p = std::filesystem::temp_directory_path() / "kfw_bench_1m_full.csv";
    std::ofstream out(p);
    out << "t,gyro,angle,truth\n";
    std::mt19937_64 rng(1);
    std::normal_distribution<double> n(0.0, 1.0);
    char line[160];
    for (int i = 0; i < 1000000; ++i) {
      const int len = std::snprintf(line, sizeof line, "%.6f,%.17g,%.17g,%.17g\n", i * 0.0035,
                                    n(rng), 10.0 * n(rng), 10.0 * n(rng));
      out.write(line, len);
    }
    return p.string();
  }();
  return path;
}

void load(benchmark::State& state, const std::string& path, const kfw::Mapping& m) {
  auto s = kfw::load_preset(KFW_SOURCE_DIR "/presets/helicopter.json");
  if (!s) {
    state.SkipWithError(s.error().c_str());
    return;
  }
  std::size_t rows = 0;
  for (auto _ : state) {
    auto d = kfw::load_dataset_file(*s->instance, path, m);
    if (!d) {
      state.SkipWithError(d.error().c_str());
      return;
    }
    rows = d->rows();
    benchmark::DoNotOptimize(d->columns.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * rows));
  state.counters["rows"] = static_cast<double>(rows);
}

void BM_LoadRealLog55k(benchmark::State& state) {
  const std::string path =
      std::string(KFW_SHARED_DIR) + "/data/broad/10_undisturbed_slow_translation_A.csv";
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  load(state, path, {});
}
BENCHMARK(BM_LoadRealLog55k)->Unit(benchmark::kMillisecond);

void BM_Load1MRows4Columns(benchmark::State& state) {
  load(state, million_row_file(), {});
}
BENCHMARK(BM_Load1MRows4Columns)->Unit(benchmark::kMillisecond)->Iterations(5);

// The same file through a mapping with a unit conversion on two roles.
void BM_Load1MRowsConverted(benchmark::State& state) {
  kfw::Mapping m;
  m["gyro"].unit = "rad/s";
  m["t"].unit = "ms";
  load(state, million_row_file(), m);
}
BENCHMARK(BM_Load1MRowsConverted)->Unit(benchmark::kMillisecond)->Iterations(5);

}  // namespace
