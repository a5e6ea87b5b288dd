// Buffer<T>: a std::vector whose resize() leaves new elements of trivial types (glm vectors,
// integers) uninitialised, as new T does, instead of zeroing them. The surface extractor sizes
// its output arrays and then writes every element, in parallel and out of order; zeroing them
// first cost a sixteenth of the extraction and a second trip of every output cache line
// through memory. Everything else behaves as std::vector<T>.
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace osteon::geometry {

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
  // Without arguments: default-initialise (the one difference from std::allocator).
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
