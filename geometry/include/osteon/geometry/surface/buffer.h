// Buffer<T>: a std::vector whose resize() leaves new elements of trivial types (glm vectors,
// integers) uninitialised, as new T does, instead of zeroing them. The surface extractor sizes
// its output arrays and then writes every element, in parallel and out of order; zeroing them
// first would send every output cache line through memory twice.
// Large arrays (1 MiB and up) are mapped directly on 2 MiB boundaries, and a freed one is
// kept for reuse by the next array of its size in 2 MiB steps (at most kCachedBufferBlocks
// arrays, kCachedBufferBytes in all, the oldest given back first), so repeated extractions
// do not take fresh pages whenever the C library would give freed arrays back to the kernel.
// Huge pages are advised for them, so a large fresh mesh takes few page faults.
// Everything else behaves as std::vector<T>. Measurements: docs/performance.md.
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace osteon::geometry {

inline constexpr std::size_t kCachedBufferBlocks = 8;
inline constexpr std::size_t kCachedBufferBytes = std::size_t(64) << 20;

// Bytes of freed large arrays kept for reuse, and how to give them back to the system (for
// instance after the last mesh of a session). Thread-safe.
std::size_t cachedBufferBytes();
void releaseCachedBuffers();

namespace detail {
inline constexpr std::size_t kLargeBufferBytes = std::size_t(1) << 20;
// Aligned to 2 MiB, huge pages advised; throws bad_alloc.
void* allocateLarge(std::size_t bytes);
void freeLarge(void* p, std::size_t bytes) noexcept;  // bytes as allocated
}  // namespace detail

template <typename T>
struct DefaultInitAllocator : std::allocator<T> {
  using std::allocator<T>::allocator;
  DefaultInitAllocator() noexcept = default;
  template <typename U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <typename U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  T* allocate(std::size_t n) {
    if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
    if (n * sizeof(T) >= detail::kLargeBufferBytes)
      return static_cast<T*>(detail::allocateLarge(n * sizeof(T)));
    return std::allocator<T>::allocate(n);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) >= detail::kLargeBufferBytes) {
      detail::freeLarge(p, n * sizeof(T));
    } else {
      std::allocator<T>::deallocate(p, n);
    }
  }
  // Without arguments: default-initialise (std::allocator value-initialises).
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <typename T, typename U>
bool operator==(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
  return true;
}
template <typename T, typename U>
bool operator!=(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
  return false;
}

template <typename T>
using Buffer = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace osteon::geometry
