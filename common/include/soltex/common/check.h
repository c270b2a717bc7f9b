#pragma once

#include <cstdio>
#include <cstdlib>

// Debug checks of internal invariants, in the manner of pbrt's DCHECK: compiled in for
// Debug and sanitizer builds (SOLTEX_ENABLE_DCHECK), and to nothing in release builds, where
// the condition is not evaluated at all. A failed check names the condition and the place,
// then aborts, so a sanitizer run stops at the first broken invariant. Bad input from outside
// never reaches these: it is refused with an error naming the bound it broke.
namespace soltex::detail {

[[noreturn]] inline void dcheck_failed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: internal check failed: %s\n", file, line, condition);
  std::abort();
}

}  // namespace soltex::detail

#if defined(SOLTEX_ENABLE_DCHECK)
#define SOLTEX_DCHECK(condition)      \
  ((condition) ? static_cast<void>(0) \
               : ::soltex::detail::dcheck_failed(#condition, __FILE__, __LINE__))
#else
#define SOLTEX_DCHECK(condition) static_cast<void>(sizeof(static_cast<bool>(condition)))
#endif
