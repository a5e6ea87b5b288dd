// Lock-free hand-offs between a device's own thread (a serial reader, a HID reader, a servo
// loop, a render loop) and the thread that polls it: one writer, one reader, no lock, no heap
// after construction.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace osteon::devices {

// The latest value, as a triple buffer: the writer never waits, the reader always gets a
// whole value (the newest published, or the one it had).
template <class T>
class LatestValue {
  static_assert(std::is_trivially_copyable_v<T>, "LatestValue holds plain data");

 public:
  LatestValue() = default;
  explicit LatestValue(const T& initial) { slots_.fill(initial); }

  // Writer thread only.
  void publish(const T& value) noexcept {
    slots_[std::size_t(back_)] = value;
    back_ = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel) & kIndex;
  }
  // Reader thread only: the newest value; true when it is newer than the last read.
  bool read(T& out) noexcept {
    bool fresh = false;
    if (middle_.load(std::memory_order_acquire) & kFresh) {
      front_ = middle_.exchange(front_, std::memory_order_acq_rel) & kIndex;
      fresh = true;
    }
    out = slots_[std::size_t(front_)];
    return fresh;
  }

 private:
  static constexpr int kIndex = 3;
  static constexpr int kFresh = 4;
  std::array<T, 3> slots_{};
  int back_ = 0;                 // writer's
  int front_ = 1;                // reader's
  std::atomic<int> middle_{2};   // index | kFresh
};

// A bounded single-producer single-consumer queue; push() fails when full (the caller counts).
template <class T>
class SpscQueue {
  static_assert(std::is_trivially_copyable_v<T>, "SpscQueue holds plain data");

 public:
  explicit SpscQueue(std::size_t capacity) : items_(capacity + 1) {}
  bool push(const T& item) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t next = head + 1 == items_.size() ? 0 : head + 1;
    if (next == tail_.load(std::memory_order_acquire)) return false;
    items_[head] = item;
    head_.store(next, std::memory_order_release);
    return true;
  }
  bool pop(T& item) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    item = items_[tail];
    tail_.store(tail + 1 == items_.size() ? 0 : tail + 1, std::memory_order_release);
    return true;
  }

 private:
  std::vector<T> items_;
  std::atomic<std::size_t> head_{0};
  std::atomic<std::size_t> tail_{0};
};

}  // namespace osteon::devices
