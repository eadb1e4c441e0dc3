// How many cores this process may run on: its CPU affinity (taskset, a cpuset, a Slurm
// allocation), not the machine's count; at least 1. The default of every parallel command
// (experiment/parallel.h) and of the CSV writer's formatting threads (data/csv.h).
#pragma once

namespace kfw {

int usable_cores();

}  // namespace kfw
