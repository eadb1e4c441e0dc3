// Process-wide allocator setting for live re-runs.
#pragma once

namespace kfw {

// Every slider move re-runs a filter that allocates its per-step arrays anew (tens of MB on long
// logs). glibc serves such blocks with fresh mmap pages, and first-touch page faults then cost
// more than the filter itself. Keeping large blocks on the heap and not trimming it makes the
// second and later runs reuse warm memory. Call once at the start of main().
void retain_freed_memory();

}  // namespace kfw
