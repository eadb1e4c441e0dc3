// One libFuzzer target per harness: built by tests/fuzz/CMakeLists.txt with
// -DKFW_FUZZ_HARNESS="name" (make fuzz). A violation prints what broke and aborts, so libFuzzer
// saves the input as a crash.
#include <cstdio>
#include <cstdlib>

#include "harness.h"

#ifndef KFW_FUZZ_HARNESS
#error "KFW_FUZZ_HARNESS names the harness (harness.h)"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string why = kfw::fuzz::run_harness(
      KFW_FUZZ_HARNESS, std::string_view(reinterpret_cast<const char*>(data), size));
  if (!why.empty()) {
    std::fprintf(stderr, "kfw fuzz %s: %s\n", KFW_FUZZ_HARNESS, why.c_str());
    std::abort();
  }
  return 0;
}
