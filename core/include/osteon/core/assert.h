// Debug assertions for the libraries' invariants: OSTEON_ASSERT(cond, "why") checks `cond` in
// debug builds and, when it is false, prints one line (file, line, why, the condition) and
// aborts: a broken invariant is osteon's bug, never the input's (that is InputError's).
// Under NDEBUG (Release) it compiles to nothing and `cond` is not evaluated, so it may sit in
// a 1 kHz loop.
#pragma once

#include <cstdio>
#include <cstdlib>

namespace osteon::detail {

[[noreturn]] inline void assertionFailed(const char* condition, const char* why, const char* file,
                                         int line) noexcept {
  std::fprintf(stderr, "osteon: internal error: %s:%d: %s (assertion %s failed)\n", file, line, why,
               condition);
  std::abort();
}

}  // namespace osteon::detail

#ifdef NDEBUG
// sizeof keeps the condition's names used (no unused-variable warning) without evaluating it.
#define OSTEON_ASSERT(cond, why) static_cast<void>(sizeof((cond) ? true : false))
#else
#define OSTEON_ASSERT(cond, why) \
  ((cond) ? static_cast<void>(0) \
          : ::osteon::detail::assertionFailed(#cond, why, __FILE__, __LINE__))
#endif
