#pragma once
/// Programmer-error checks. DEXCLOTH_DEMAND is always on; DEXCLOTH_ASSERT only in debug builds
/// (use it in inner loops). Input validation never uses either: it reports errors instead.

namespace dexcloth::detail {
[[noreturn]] void demand_failed(const char* cond, const char* file, int line);
}  // namespace dexcloth::detail

#define DEXCLOTH_DEMAND(cond) \
  ((cond) ? static_cast<void>(0) : ::dexcloth::detail::demand_failed(#cond, __FILE__, __LINE__))

#ifdef NDEBUG
#define DEXCLOTH_ASSERT(cond) static_cast<void>(0)
#else
#define DEXCLOTH_ASSERT(cond) DEXCLOTH_DEMAND(cond)
#endif
