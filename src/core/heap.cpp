#include "core/heap.hpp"

#include <cstdlib>  // defines __GLIBC__ on glibc: without a system header first, the test below
                    // never held and the setting was never made

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
