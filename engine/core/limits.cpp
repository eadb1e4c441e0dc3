#include "core/limits.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace kfw::limits {

namespace {

// A cgroup file's number ("max" or unreadable: none).
std::uint64_t read_limit(const char* path) {
  std::ifstream in(path);
  std::string s;
  if (!(in >> s) || s.empty() || s == "max") return 0;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
  return end && *end == '\0' ? v : 0;
}

std::uint64_t physical_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 8 * kGiB;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
}

}  // namespace

std::uint64_t max_bytes(Input kind) {
  switch (kind) {
    case Input::kData:
      return kDataBytes;
    case Input::kPart:
      return kPartBytes;
    default:
      return kJsonBytes;
  }
}

const char* input_name(Input kind) {
  switch (kind) {
    case Input::kData:
      return "data file";
    case Input::kPreset:
      return "preset";
    case Input::kModel:
      return "model file";
    case Input::kMapping:
      return "mapping";
    case Input::kSession:
      return "session";
    case Input::kPart:
      return "part";
  }
  return "file";
}

namespace {

std::uint64_t read_memory_bytes() {
  if (const char* e = std::getenv(kMemoryLimitEnv); e && *e) {
    char* end = nullptr;
    const unsigned long long v = std::strtoull(e, &end, 10);
    if (end && *end == '\0' && v > 0) return v;
  }
  std::uint64_t m = physical_bytes();
  for (const char* p :
       {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    const std::uint64_t c = read_limit(p);
    if (c > 0) m = std::min(m, c);
  }
  struct rlimit rl {};
  if (::getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
    m = std::min<std::uint64_t>(m, rl.rlim_cur);  // ulimit -v
  return m;
}

}  // namespace

// Read once per process: a Monte Carlo run simulates thousands of times.
std::uint64_t memory_bytes() {
  static const std::uint64_t bytes = read_memory_bytes();
  return bytes;
}

std::size_t max_sim_rows(std::size_t columns) {
  const std::uint64_t per_row = 8u * std::max<std::size_t>(columns, 1);
  const std::uint64_t rows = memory_bytes() / 4 / per_row;
  return static_cast<std::size_t>(std::min<std::uint64_t>(rows, kMaxSimRows));
}

std::string bytes_text(std::uint64_t b) {
  // MB and GB of 2^20 and 2^30 bytes, as the messages have always said ("the 10 MB limit").
  char buf[64];
  const auto unit = [&](std::uint64_t u, const char* name) {
    if (b % u == 0) {
      std::snprintf(buf, sizeof buf, "%llu %s", static_cast<unsigned long long>(b / u), name);
    } else {
      std::snprintf(buf, sizeof buf, "%.1f %s", static_cast<double>(b) / static_cast<double>(u),
                    name);
    }
  };
  if (b >= kGiB) {
    unit(kGiB, "GB");
  } else if (b >= kMiB) {
    unit(kMiB, "MB");
  } else {
    std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(b));
  }
  return buf;
}

}  // namespace kfw::limits
