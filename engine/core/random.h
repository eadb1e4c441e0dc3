// The random-number specification of kfw's simulators (presets/models/README.md, "Random
// numbers"): the same streams on every platform and standard library. std::normal_distribution is
// not used — its algorithm differs between libraries.
//   engine   std::mt19937_64 (its output sequence is fixed by the C++ standard)
//   stream   seeded by splitmix64(seed XOR FNV-1a-64(stream name)): one stream per noise source
//   uniform  u = (⌊x / 2¹¹⌋ + ½) · 2⁻⁵³, in (0, 1] (1 only when the sum rounds up, p = 2⁻⁵³)
//   normal   Box–Muller, one draw per two uniforms: √(−2 ln u₁) · cos(2π u₂)
#pragma once

#include <cstdint>
#include <random>
#include <string_view>

namespace kfw {

class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::string_view stream);
  double uniform();
  double normal();

 private:
  std::mt19937_64 engine_;
};

}  // namespace kfw
