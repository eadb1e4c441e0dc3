// Benchmark main: the same allocator setting as the applications (core/memory.h).
#include <benchmark/benchmark.h>

#include <cstdio>

#include "core/memory.h"
#include "native/native_model.h"

int main(int argc, char** argv) {
  kfw::retain_freed_memory();
  // KFW_NATIVE=1: the model benchmarks on the native path (native/native_model.h).
  if (const std::string n = kfw::native::enable_from_environment(); !n.empty())
    std::fprintf(stderr, "kfw_bench: %s\n", n.c_str());
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
