// Independent work items on every core: the sweep's grid points, the tuner's per-log runs, its
// scale checks and its concurrent starts. Results go to pre-sized slots, so the order of the
// output never depends on the number of threads.
#pragma once

#include <cstddef>
#include <functional>

namespace kfw {

// `requested` threads, or for 0 every core this process may run on (its CPU affinity: taskset,
// a Slurm allocation or a cpuset; at least 1).
int worker_count(int requested = 0);

// Calls fn(i) for i in [0, n) on up to `threads` threads (0: every core); returns when all are
// done. fn must not throw.
void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& fn);

}  // namespace kfw
