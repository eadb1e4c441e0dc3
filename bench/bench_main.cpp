// Benchmark main: the same allocator setting as the applications (core/memory.h).
#include <benchmark/benchmark.h>

#include "core/memory.h"

int main(int argc, char** argv) {
  kfw::retain_freed_memory();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
