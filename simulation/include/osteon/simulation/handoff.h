// Lock-free hand-offs between the runtime's threads (one writer, one reader each): a triple
// buffer for "the latest value" (pose to the collision thread, force to the haptic thread) and
// a bounded ring for a stream (changed bricks to the visual thread). Neither allocates after
// construction, locks or throws.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace osteon::simulation {

template <typename T>
class TripleBuffer {
 public:
  // Publishes a value; the reader sees it, or a later one, on its next read.
  void write(const T& value) {
    slots_[back_] = value;
    back_ = middle_.exchange(std::uint8_t(back_ | kFresh), std::memory_order_acq_rel) & kIndex;
  }
  // The latest value published (the initial T() before any). Sets `fresh` if it is new.
  const T& read(bool* fresh = nullptr) {
    const bool isNew = (middle_.load(std::memory_order_acquire) & kFresh) != 0;
    if (isNew) front_ = middle_.exchange(front_, std::memory_order_acq_rel) & kIndex;
    if (fresh) *fresh = isNew;
    return slots_[front_];
  }

 private:
  static constexpr std::uint8_t kFresh = 4;
  static constexpr std::uint8_t kIndex = 3;
  T slots_[3]{};
  std::uint8_t back_ = 0;                 // writer's slot
  std::atomic<std::uint8_t> middle_{1};   // the hand-over slot, with the fresh bit
  std::uint8_t front_ = 2;                // reader's slot
};

template <typename T>
class SpscRing {
 public:
  explicit SpscRing(std::size_t capacity) : slots_(capacity + 1) {}
  // False (and nothing written) when full.
  bool push(const T& value) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t next = head + 1 == slots_.size() ? 0 : head + 1;
    if (next == tail_.load(std::memory_order_acquire)) return false;
    slots_[head] = value;
    head_.store(next, std::memory_order_release);
    return true;
  }
  bool pop(T& value) {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    value = slots_[tail];
    tail_.store(tail + 1 == slots_.size() ? 0 : tail + 1, std::memory_order_release);
    return true;
  }

 private:
  std::vector<T> slots_;
  alignas(64) std::atomic<std::size_t> head_{0};  // written by the producer
  alignas(64) std::atomic<std::size_t> tail_{0};  // written by the consumer
};

}  // namespace osteon::simulation
