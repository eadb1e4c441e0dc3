#include "experiment/grammar.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "core/param_spec.h"
#include "core/suggest.h"

namespace kfw {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && s.front() == ' ')
    s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ')
    s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  for (;;) {
    const auto at = s.find(sep);
    parts.push_back(s.substr(0, at));
    if (at == std::string_view::npos) return parts;
    s.remove_prefix(at + 1);
  }
}

// A whole number: optional '-', digits, nothing else.
bool parse_integer(std::string_view text, long long& out) {
  text = trim(text);
  if (text.empty()) return false;
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end;
}

bool parse_count(std::string_view text, std::size_t& out) {
  text = trim(text);
  if (text.empty() || text.front() == '-') return false;
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end;
}

Error grammar_error(std::string_view option, std::string_view text, std::string_view form,
                    const std::string& reason) {
  return Error{std::string(option) + ": " + quote_token(text) + " is not " + std::string(form) +
               ": " + reason};
}

}  // namespace

std::vector<double> Grid::values(bool log) const {
  std::vector<double> v;
  v.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double f = n == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
    v.push_back(log ? std::pow(10.0, std::log10(lo) + f * (std::log10(hi) - std::log10(lo)))
                    : lo + f * (hi - lo));
  }
  if (n > 1) v.back() = hi;  // exactly hi, not hi ± rounding
  return v;
}

Expected<Grid> parse_grid(std::string_view text, std::string_view option) {
  constexpr std::string_view kForm = "a grid lo:hi:n[:log]";
  const auto fields = split(text, ':');
  if (fields.size() < 3 || fields.size() > 4) {
    return grammar_error(option, text, kForm, "expected lo:hi:n with an optional :log or :lin");
  }
  Grid g;
  if (!parse_double(fields[0], g.lo)) {
    return grammar_error(option, text, kForm, "lo " + quote_token(fields[0]) + " is not a number");
  }
  if (!parse_double(fields[1], g.hi)) {
    return grammar_error(option, text, kForm, "hi " + quote_token(fields[1]) + " is not a number");
  }
  if (!parse_count(fields[2], g.n) || g.n < 1) {
    return grammar_error(option, text, kForm,
                         "n " + quote_token(fields[2]) + " is not a whole number >= 1");
  }
  if (g.n > kMaxGridPoints) {
    return grammar_error(option, text, kForm,
                         "n is more than " + std::to_string(kMaxGridPoints) + " points");
  }
  if (fields.size() == 4) {
    const std::string_view s = trim(fields[3]);
    if (s == "log") {
      g.spacing = Spacing::kLog;
    } else if (s == "lin") {
      g.spacing = Spacing::kLinear;
    } else {
      return grammar_error(option, text, kForm, unknown_message("spacing", s, {"log", "lin"}));
    }
  }
  if (g.spacing == Spacing::kLog && (g.lo <= 0 || g.hi <= 0)) {
    return grammar_error(option, text, kForm, "log spacing needs lo, hi > 0");
  }
  return g;
}

Expected<std::vector<long long>> parse_int_set(std::string_view text, std::string_view option) {
  constexpr std::string_view kForm = "a set of integers such as 1..50 or 3,7,9";
  if (trim(text).empty()) return grammar_error(option, text, kForm, "it is empty");
  // Count first, expand after: "1..1000000000000" must not allocate.
  struct Range {
    long long lo, hi;
  };
  std::vector<Range> ranges;
  unsigned long long members = 0;
  for (std::string_view part : split(text, ',')) {
    part = trim(part);
    if (part.empty()) return grammar_error(option, text, kForm, "an element is empty");
    Range r{};
    const auto dots = part.find("..");
    if (dots == std::string_view::npos) {
      if (!parse_integer(part, r.lo)) {
        return grammar_error(option, text, kForm, quote_token(part) + " is not a whole number");
      }
      r.hi = r.lo;
    } else {
      const auto a = part.substr(0, dots), b = part.substr(dots + 2);
      if (!parse_integer(a, r.lo) || !parse_integer(b, r.hi)) {
        return grammar_error(option, text, kForm,
                             quote_token(part) + " is not a range a..b of whole numbers");
      }
      if (r.lo > r.hi) {
        return grammar_error(option, text, kForm,
                             "the range " + quote_token(part) + " is reversed (a > b)");
      }
    }
    const auto size =
        static_cast<unsigned long long>(r.hi) - static_cast<unsigned long long>(r.lo) + 1;
    if (size == 0 || size > kMaxSetMembers || (members += size) > kMaxSetMembers) {
      return grammar_error(option, text, kForm,
                           "more than " + std::to_string(kMaxSetMembers) + " members");
    }
    ranges.push_back(r);
  }
  std::vector<long long> out;
  out.reserve(members);
  for (const auto& r : ranges) {
    for (long long v = r.lo;; ++v) {
      out.push_back(v);
      if (v == r.hi) break;
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

Expected<Shard> parse_shard(std::string_view text, std::string_view option) {
  constexpr std::string_view kForm = "a shard i/N";
  const auto fields = split(text, '/');
  Shard s;
  if (fields.size() != 2 || !parse_count(fields[0], s.index) || !parse_count(fields[1], s.count)) {
    return grammar_error(option, text, kForm, "expected two whole numbers i/N");
  }
  if (s.count < 1 || s.index < 1 || s.index > s.count) {
    return grammar_error(option, text, kForm, "needs 1 <= i <= N");
  }
  return s;
}

bool in_shard(std::size_t index, const Shard& shard) {
  return shard.count > 0 && index % shard.count == shard.index - 1;
}

const char* value_grammar_help() {
  return "Value grammar (the same wherever an option takes one of these forms):\n"
         "  grid   lo:hi:n        n points from lo to hi, both included (n >= 1, whole;\n"
         "                        n = 1 gives lo alone)\n"
         "         lo:hi:n:log    the same, evenly spaced in log10 (lo, hi > 0);\n"
         "         lo:hi:n:lin    linear spacing; without a suffix, sweep --param spaces a\n"
         "                        log-scale parameter in log10 and others linearly\n"
         "  set    1..50          whole numbers: ranges a..b (a <= b) and single values,\n"
         "         3,7,9  1..5,9  comma-separated; at most 1000000 members\n"
         "  shard  i/N            1 <= i <= N: work items (grid points in row-major order,\n"
         "                        seeds, logs) numbered from 0 go to shard i when\n"
         "                        index mod N = i - 1\n";
}

}  // namespace kfw
