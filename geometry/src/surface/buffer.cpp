#include "osteon/geometry/surface/buffer.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace osteon::geometry {

namespace {

constexpr std::size_t kHugePage = std::size_t(2) << 20;
// Every large block: a fresh 4 KiB page costs 2.2 us to fault in on a virtual machine (its
// allocation and zeroing, the host's backing; faulted, pre-populated or MADV_POPULATE_WRITE
// alike) against 0.2 ms for a 2 MiB one, and a fresh process's first extraction writes
// only fresh pages: `osteon mesh` on a 128^3 sphere (two 2.8 MiB arrays) took 7.7 ms with
// 4 KiB pages against 4.3 ms advised (docs/performance.md, "Surface extraction").
constexpr std::size_t kHugeAdviceBytes = detail::kLargeBufferBytes;

std::size_t roundedBytes(std::size_t bytes) {
  return (bytes + kHugePage - 1) / kHugePage * kHugePage;
}

// A fresh block of `bytes` (a multiple of 2 MiB) on a 2 MiB boundary, or nullptr.
void* mapBlock(std::size_t bytes, bool hugePages) {
#if defined(__linux__)
  // Mapped directly, not through malloc: the C library would give a freed block back to the
  // kernel or keep it at its own discretion, which is what the cache below decides instead.
  const std::size_t span = bytes + kHugePage;
  void* raw = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) return nullptr;
  const auto start = reinterpret_cast<std::uintptr_t>(raw);
  const std::uintptr_t aligned = (start + kHugePage - 1) & ~(kHugePage - 1);
  if (aligned > start) munmap(raw, aligned - start);
  if (start + span > aligned + bytes)
    munmap(reinterpret_cast<void*>(aligned + bytes), start + span - (aligned + bytes));
  void* p = reinterpret_cast<void*>(aligned);
#if defined(MADV_HUGEPAGE)
  // Advice only: where transparent huge pages are off, this fails and nothing changes. Where
  // memory is fragmented the kernel may wait to compact a huge page (20 ms once in ten runs
  // on one day), a cost every extraction of 8 MiB and up already risked.
  if (hugePages) (void)madvise(p, bytes, MADV_HUGEPAGE);
#endif
  return p;
#else
  (void)hugePages;
  return std::aligned_alloc(kHugePage, bytes);
#endif
}

void unmapBlock(void* p, std::size_t bytes) noexcept {
#if defined(__linux__)
  munmap(p, bytes);
#else
  (void)bytes;
  std::free(p);
#endif
}

struct Block {
  void* p = nullptr;
  std::size_t bytes = 0;
};

// Blocks taken out of the cache, given back to the system once the lock is released (an
// unmap of touched memory takes a while; other threads need not wait for it).
struct Victims {
  Block blocks[kCachedBufferBlocks];
  std::size_t count = 0;
  ~Victims() {
    for (std::size_t i = 0; i < count; ++i) unmapBlock(blocks[i].p, blocks[i].bytes);
  }
};

// Freed blocks, oldest first. A fixed array: no allocation while the lock is held.
struct BlockCache {
  std::mutex mutex;
  Block blocks[kCachedBufferBlocks];
  std::size_t count = 0;
  std::size_t bytes = 0;

  void takeOldest(Victims& victims) {  // with the lock held
    victims.blocks[victims.count++] = blocks[0];
    bytes -= blocks[0].bytes;
    for (std::size_t i = 1; i < count; ++i) blocks[i - 1] = blocks[i];
    --count;
  }
};

BlockCache& cache() {
  static BlockCache* c = new BlockCache;  // never destroyed: blocks may be freed during exit
  return *c;
}

}  // namespace

std::size_t cachedBufferBytes() {
  BlockCache& c = cache();
  const std::lock_guard<std::mutex> lock(c.mutex);
  return c.bytes;
}

void releaseCachedBuffers() {
  Victims victims;  // declared first: unmapped after the lock is released
  BlockCache& c = cache();
  const std::lock_guard<std::mutex> lock(c.mutex);
  while (c.count > 0) c.takeOldest(victims);
}

namespace detail {

void* allocateLarge(std::size_t bytes) {
  if (bytes > std::size_t(PTRDIFF_MAX)) throw std::bad_alloc();  // and its rounding cannot wrap
  const std::size_t rounded = roundedBytes(bytes);
  {
    BlockCache& c = cache();
    const std::lock_guard<std::mutex> lock(c.mutex);
    for (std::size_t i = c.count; i-- > 0;) {  // the newest first: its lines may still be cached
      if (c.blocks[i].bytes != rounded) continue;
      void* p = c.blocks[i].p;
      for (std::size_t j = i + 1; j < c.count; ++j) c.blocks[j - 1] = c.blocks[j];
      --c.count;
      c.bytes -= rounded;
      return p;
    }
  }
  // Huge pages by the size asked for, not the rounded size.
  const bool hugePages = bytes >= kHugeAdviceBytes;
  void* p = mapBlock(rounded, hugePages);
  if (p == nullptr) {  // out of memory: give back what the cache holds, then try once more
    releaseCachedBuffers();
    p = mapBlock(rounded, hugePages);
    if (p == nullptr) throw std::bad_alloc();
  }
  return p;
}

void freeLarge(void* p, std::size_t bytes) noexcept {
  const std::size_t rounded = roundedBytes(bytes);
  if (rounded <= kCachedBufferBytes) {
    Victims victims;  // declared first: unmapped after the lock is released
    BlockCache& c = cache();
    const std::lock_guard<std::mutex> lock(c.mutex);
    while (c.count > 0 &&
           (c.count == kCachedBufferBlocks || c.bytes + rounded > kCachedBufferBytes)) {
      c.takeOldest(victims);
    }
    c.blocks[c.count++] = {p, rounded};
    c.bytes += rounded;
    return;
  }
  unmapBlock(p, rounded);
}

}  // namespace detail

}  // namespace osteon::geometry
