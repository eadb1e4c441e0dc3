#include "experiment/parallel.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

#include "core/cores.h"

namespace kfw {

int worker_count(int requested) {
  if (requested > 0) return requested;
  return usable_cores();
}

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& fn) {
  const auto workers = std::min<std::size_t>(static_cast<std::size_t>(worker_count(threads)), n);
  if (workers <= 1) {
    for (std::size_t i = 0; i < n; ++i)
      fn(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i = next++; i < n; i = next++)
      fn(i);
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < workers; ++t)
    pool.emplace_back(work);
  work();
  for (auto& t : pool)
    t.join();
}

}  // namespace kfw
