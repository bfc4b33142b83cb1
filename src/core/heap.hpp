#pragma once
/// Process-wide allocator settings for programs that step a world (the CLI, the benchmarks).

namespace dexcloth {

/// Keeps 64 MB at the top of glibc's heap instead of returning freed memory to the kernel.
/// Eigen's dense products (the friction problem's Schur complement) allocate megabytes of
/// packing buffers per call; glibc gave them back after each step and page-faulted them in
/// again, a third of fold_napkin's interface time. No effect on results; a no-op elsewhere.
void keep_heap_top();

}  // namespace dexcloth
