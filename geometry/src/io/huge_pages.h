// Advice that a large fresh array be backed by transparent huge pages: on a virtual machine a
// 4 KiB page's first touch costs a fault of microseconds, as much as a thousand voxels' work,
// and a volume's arrays are touched once each. The memory is still freed as usual.
#pragma once

#include <cstddef>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace osteon::geometry {

// Advises the whole 2 MiB pages within [p, p + bytes), for arrays of 8 MiB and more (below,
// the kernel's occasional wait to find huge pages outweighs what they save). Advice only:
// where huge pages are off it fails and nothing changes.
inline void adviseHugePages(void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;
  if (bytes < (std::size_t(8) << 20)) return;
  const auto first = (reinterpret_cast<std::uintptr_t>(p) + kHugePage - 1) & ~(kHugePage - 1);
  const auto last = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(kHugePage - 1);
  if (last > first) (void)madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

}  // namespace osteon::geometry
