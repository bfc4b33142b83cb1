#pragma once
/// Process-wide allocator settings for programs that step a world (the CLI, the benchmarks).

namespace dexcloth {

/// Keeps 64 MB at the top of glibc's heap instead of returning freed memory to the kernel.
/// Eigen's dense products (the friction problem's Schur complement) allocate megabytes of
/// packing buffers per call, which glibc gave back after each step and page-faulted in again:
/// fold_napkin took 156k page faults without this, 7.7k with it (whole run 8.1–8.4 → 7.8–8.4 s,
/// within this machine's noise). No effect on results; a no-op elsewhere.
void keep_heap_top();

}  // namespace dexcloth
