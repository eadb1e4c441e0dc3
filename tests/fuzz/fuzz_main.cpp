// One libFuzzer target per harness, built by tests/fuzz/CMakeLists.txt (make fuzz): this file once,
// plus a one-line source per target defining kfw_fuzz_harness, the harness's name. A violation
// prints what broke and aborts, so libFuzzer saves the input as a crash.
#include <cstdio>
#include <cstdlib>

#include "harness.h"

extern const char* const kfw_fuzz_harness;  // harness.h's name, one per target

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string why = kfw::fuzz::run_harness(
      kfw_fuzz_harness, std::string_view(reinterpret_cast<const char*>(data), size));
  if (!why.empty()) {
    std::fprintf(stderr, "kfw fuzz %s: %s\n", kfw_fuzz_harness, why.c_str());
    std::abort();
  }
  return 0;
}
