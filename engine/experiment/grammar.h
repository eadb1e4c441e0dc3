// One value grammar for every command-line option that takes a grid, a set of integers or a
// shard (README "Value grammar"; `kfw-cli help grammar` prints value_grammar_help()).
//   grid   lo:hi:n[:log|:lin]   n >= 1 points from lo to hi, both included
//   set    1..50, 3,7,9, 1..5,9 whole numbers, ranges a..b with a <= b
//   shard  i/N                  1 <= i <= N; item `index` (from 0) is in shard i when
//                               index mod N = i - 1
// Errors name the option and quote the text (truncated).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"
#include "core/limits.h"

namespace kfw {

inline constexpr std::size_t kMaxGridPoints = limits::kMaxGridPoints;
inline constexpr std::size_t kMaxSetMembers = limits::kMaxSetMembers;

enum class Spacing {
  kDefault,  // no suffix: the caller decides (sweep: the parameter's scale)
  kLinear,   // ":lin"
  kLog,      // ":log"
};

struct Grid {
  double lo = 0.0, hi = 1.0;
  std::size_t n = 1;
  Spacing spacing = Spacing::kDefault;
  // The n points, lo and hi included (n = 1: lo); `log` spaces them evenly in log10.
  std::vector<double> values(bool log) const;
};

// "lo:hi:n", "lo:hi:n:log", "lo:hi:n:lin". lo, hi finite; n whole, 1..kMaxGridPoints; ":log"
// needs lo, hi > 0.
Expected<Grid> parse_grid(std::string_view text, std::string_view option);

// "1..50", "3,7,9", "1..5,9": the members, sorted, without duplicates. Rejects an empty set or
// element, a reversed range, a non-integer, more than kMaxSetMembers members.
Expected<std::vector<long long>> parse_int_set(std::string_view text, std::string_view option);

struct Shard {
  std::size_t index = 1;  // i, from 1
  std::size_t count = 1;  // N
};

// "i/N" with whole numbers 1 <= i <= N.
Expected<Shard> parse_shard(std::string_view text, std::string_view option);

// True when work item `index` (from 0: grid points in row-major order, seeds, logs) belongs to
// the shard: index mod N = i - 1.
bool in_shard(std::size_t index, const Shard& shard);

// The grammar as help text, for `kfw-cli help grammar` and the top-level help.
const char* value_grammar_help();

}  // namespace kfw
