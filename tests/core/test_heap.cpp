/// keep_heap_top: freed memory stays in the process, so blocks allocated again every step are
/// not page-faulted in again (an include-order slip once made it a silent no-op).
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/heap.hpp"

namespace {

long minor_faults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

/// Page faults over `rounds` of allocating, touching and freeing four 120 kB blocks: below
/// glibc's mapping threshold (128 kB), so they come from the heap, and 480 kB freed at its top,
/// which glibc returns to the kernel unless told to keep it.
long faults_of_reused_blocks(int rounds) {
  constexpr std::size_t kBlock = 120 * 1024;
  const long before = minor_faults();
  for (int r = 0; r < rounds; ++r) {
    std::vector<void*> blocks;
    for (int k = 0; k < 4; ++k) {
      void* p = std::malloc(kBlock);
      std::memset(p, r, kBlock);
      blocks.push_back(p);
    }
    for (auto it = blocks.rbegin(); it != blocks.rend(); ++it) std::free(*it);
  }
  return minor_faults() - before;
}

}  // namespace

#if defined(__GLIBC__)
TEST(Heap, KeptTopServesReusedBlocksWithoutPageFaults) {
  dexcloth::keep_heap_top();
  faults_of_reused_blocks(2);  // the heap grows once
  // 100 rounds: 2,800 faults when each round's freed top went back to the kernel (measured).
  EXPECT_LT(faults_of_reused_blocks(100), 200);
}
#endif
