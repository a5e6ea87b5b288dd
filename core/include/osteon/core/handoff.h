// Lock-free hand-offs between two threads, one writer and one reader each: a device's own thread
// and its poller, the runtime's haptic, collision, visual and logging threads, the viewer's
// render loop. A triple buffer hands over "the latest value" (a pose, a force, a device state);
// a ring hands over a stream in order (changed bricks, log rows, device events).
//
// Rules: T is plain data (trivially copyable, so a copy is a memcpy and never throws); nothing
// here allocates, locks or throws, construction included; each end is used from one thread
// only. Indices and slots sit on cache lines of their own, so the writer's stores do not evict
// the reader's line.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace osteon::core {

// A cache line on the machines osteon runs on (x86-64, ARM64); a constant rather than
// std::hardware_destructive_interference_size, whose value may change between compilers.
inline constexpr std::size_t kCacheLineBytes = 64;

// The latest value: write() never waits, read() always gets a whole value, the newest written
// or, when nothing new came, the one it read last (T() before any write).
template <class T>
class TripleBuffer {
  static_assert(std::is_trivially_copyable_v<T>, "TripleBuffer holds plain data");

 public:
  TripleBuffer() noexcept = default;

  // Writer thread only. The reader sees this value, or a later one, on its next read.
  void write(const T& value) noexcept {
    slots_[back_].value = value;
    back_ = std::uint8_t(middle_.exchange(std::uint8_t(back_ | kFresh), std::memory_order_acq_rel) &
                         kIndex);
  }

  // Reader thread only: the newest value, valid until the next read; `fresh` (when given) is set
  // to whether it is newer than the last read.
  const T& read(bool* fresh = nullptr) noexcept {
    const bool isNew = (middle_.load(std::memory_order_acquire) & kFresh) != 0;
    if (isNew) front_ = std::uint8_t(middle_.exchange(front_, std::memory_order_acq_rel) & kIndex);
    if (fresh) *fresh = isNew;
    return slots_[front_].value;
  }

 private:
  static constexpr std::uint8_t kIndex = 3;
  static constexpr std::uint8_t kFresh = 4;
  struct alignas(kCacheLineBytes) Slot {
    T value{};
  };
  std::array<Slot, 3> slots_{};
  alignas(kCacheLineBytes) std::uint8_t back_ = 0;                // the writer's slot
  alignas(kCacheLineBytes) std::atomic<std::uint8_t> middle_{1};  // the hand-over slot | kFresh
  alignas(kCacheLineBytes) std::uint8_t front_ = 2;               // the reader's slot
};

// A bounded queue of N items in order: push() refuses when full (the caller counts the loss),
// pop() when empty. N is a power of two, so positions run on and wrap by a mask.
template <class T, std::size_t N>
class SpscRing {
  static_assert(std::is_trivially_copyable_v<T>, "SpscRing holds plain data");
  static_assert(N > 0 && (N & (N - 1)) == 0, "SpscRing's capacity is a power of two");

 public:
  static constexpr std::size_t kCapacity = N;

  SpscRing() noexcept = default;

  // Producer thread only. False (and nothing written) when full.
  bool push(const T& value) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) == N) return false;
    slots_[head & (N - 1)] = value;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  // Consumer thread only. False when empty.
  bool pop(T& value) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    value = slots_[tail & (N - 1)];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

 private:
  alignas(kCacheLineBytes) std::atomic<std::size_t> head_{0};  // items pushed, ever
  alignas(kCacheLineBytes) std::atomic<std::size_t> tail_{0};  // items popped, ever
  alignas(kCacheLineBytes) std::array<T, N> slots_{};
};

}  // namespace osteon::core
