#include "core/assert.hpp"

#include <cstdio>
#include <cstdlib>

namespace dexcloth::detail {

void demand_failed(const char* cond, const char* file, int line) {
  std::fprintf(stderr, "dexcloth: internal error: %s failed at %s:%d\n", cond, file, line);
  std::abort();
}

}  // namespace dexcloth::detail
