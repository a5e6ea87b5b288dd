#include "support/allocation_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<std::uint64_t> gAllocations{0};
thread_local std::uint64_t tAllocations =
    0;  // constant-initialised: its first use allocates nothing

void* counted(std::size_t size) {
  gAllocations.fetch_add(1, std::memory_order_relaxed);
  ++tAllocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
}  // namespace

// Out of line, so the compiler does not pair an inlined malloc with the library's delete. Every
// form that pairs with the plain delete (nothrow too: std::stable_sort's buffer) is replaced,
// or a sanitizer sees its own operator new freed by this free.
__attribute__((noinline)) void* operator new(std::size_t size) {
  return counted(size);
}
__attribute__((noinline)) void* operator new[](std::size_t size) {
  return counted(size);
}
__attribute__((noinline)) void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return counted(size);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
__attribute__((noinline)) void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return operator new(size, std::nothrow);
}
__attribute__((noinline)) void operator delete(void* p) noexcept {
  std::free(p);
}
__attribute__((noinline)) void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
__attribute__((noinline)) void operator delete[](void* p) noexcept {
  std::free(p);
}
__attribute__((noinline)) void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
__attribute__((noinline)) void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
__attribute__((noinline)) void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}

namespace osteon::test {
std::uint64_t allocations() {
  return gAllocations.load(std::memory_order_relaxed);
}
std::uint64_t threadAllocations() {
  return tAllocations;
}
}  // namespace osteon::test
