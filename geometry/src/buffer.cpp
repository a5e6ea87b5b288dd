#include "osteon/geometry/buffer.h"

#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace osteon::geometry::detail {

namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
}

void* allocateLarge(std::size_t bytes) {
  const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
  void* p = std::aligned_alloc(kHugePage, rounded);
  if (p == nullptr) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // Advice only: where transparent huge pages are off, this fails and nothing changes.
  (void)madvise(p, rounded, MADV_HUGEPAGE);
#endif
  return p;
}

void freeLarge(void* p) noexcept { std::free(p); }

}  // namespace osteon::geometry::detail
