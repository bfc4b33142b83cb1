#include "core/heap.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dexcloth {

void keep_heap_top() {
#if defined(__GLIBC__)
  mallopt(M_TOP_PAD, 64 << 20);
#endif
}

}  // namespace dexcloth
