#pragma once
/// Process-wide allocator settings for programs that step a world (the CLI, the benchmarks).

namespace dexcloth {

/// Keeps 64 MB at the top of glibc's heap instead of returning freed memory to the kernel, so
/// blocks freed and allocated again every step are not page-faulted in again. Written for the
/// packing buffers of Eigen's products in the friction's Schur complement (fold_napkin: 156k
/// page faults without it, 7.7k with it); since that algebra runs on OpenBLAS it still halves
/// the faults of dress_sleeve (14.6k → 7.6k) and grab_pile (24.3k → 12.5k), fold_napkin 7.8k →
/// 6.8k (`perf stat -e page-faults`, 4 Dec). No effect on results; a no-op elsewhere.
void keep_heap_top();

}  // namespace dexcloth
