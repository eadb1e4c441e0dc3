// Time bounds in tests are multiplied by kTimeScale: under AddressSanitizer (make sanitize, GCC or
// clang) the code runs several times slower and every kfw-cli process takes longer to start.
#pragma once

namespace kfw::testing {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr int kTimeScale = 10;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr int kTimeScale = 10;
#else
inline constexpr int kTimeScale = 1;
#endif
#else
inline constexpr int kTimeScale = 1;
#endif

}  // namespace kfw::testing
