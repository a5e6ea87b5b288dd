// The lock-free hand-offs (core/handoff.h): their rules on one thread, then a writer and a
// reader hammering each on two threads. Run under TSan too (scripts/test --sanitize thread),
// which checks that the release/acquire pairs publish every byte of a slot.
#include "osteon/core/handoff.h"

#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <thread>
#include <utility>

#include <gtest/gtest.h>

namespace osteon::core {
namespace {

// A value whose every word follows from its sequence number, so a torn copy (words of two
// writes) is seen: the words are a fixed-seed hash of the sequence number.
struct Stamped {
  std::uint64_t seq = 0;
  std::array<std::uint64_t, 7> words{};
};

std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

constexpr std::uint64_t kSeed = 20261126;

Stamped stamped(std::uint64_t seq) {
  Stamped s;
  s.seq = seq;
  for (std::size_t i = 0; i < s.words.size(); ++i) s.words[i] = mix(kSeed ^ (seq * 8 + i));
  return s;
}

bool whole(const Stamped& s) {
  if (s.seq == 0) {
    for (std::uint64_t w : s.words) {
      if (w != 0) return false;
    }
    return true;
  }
  return s.words == stamped(s.seq).words;
}

static_assert(noexcept(TripleBuffer<Stamped>()) && noexcept(SpscRing<Stamped, 8>()));
static_assert(noexcept(std::declval<TripleBuffer<Stamped>&>().write(Stamped{})));
static_assert(noexcept(std::declval<TripleBuffer<Stamped>&>().read()));
static_assert(noexcept(std::declval<SpscRing<Stamped, 8>&>().push(Stamped{})));
static_assert(noexcept(std::declval<SpscRing<Stamped, 8>&>().pop(std::declval<Stamped&>())));
static_assert(alignof(TripleBuffer<int>) >= kCacheLineBytes &&
              alignof(SpscRing<int, 8>) >= kCacheLineBytes);
// Three slots and three indices, each on a line of its own.
static_assert(sizeof(TripleBuffer<int>) >= 6 * kCacheLineBytes);

TEST(Handoff, TripleBufferGivesTheNewestValueAndSaysWhenItIsNew) {
  TripleBuffer<int> buffer;
  bool fresh = true;
  EXPECT_EQ(buffer.read(&fresh), 0);  // T() before any write
  EXPECT_FALSE(fresh);
  buffer.write(1);
  buffer.write(2);
  EXPECT_EQ(buffer.read(&fresh), 2);
  EXPECT_TRUE(fresh);
  EXPECT_EQ(buffer.read(&fresh), 2);  // nothing new: the one read last
  EXPECT_FALSE(fresh);
  for (int i = 3; i < 20; ++i) {
    buffer.write(i);
    EXPECT_EQ(buffer.read(&fresh), i);
    EXPECT_TRUE(fresh);
  }
}

TEST(Handoff, RingHoldsExactlyItsCapacityInOrderAcrossWraps) {
  SpscRing<int, 4> ring;
  int v = 0;
  EXPECT_FALSE(ring.pop(v));
  int next = 0, expected = 0;
  for (int round = 0; round < 10; ++round) {  // positions wrap the 4 slots many times
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.push(next++));
    EXPECT_FALSE(ring.push(-1));  // full: refused, nothing overwritten
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(ring.pop(v));
      EXPECT_EQ(v, expected++);
    }
    EXPECT_TRUE(ring.push(next++));
    while (ring.pop(v)) EXPECT_EQ(v, expected++);
  }
  EXPECT_EQ(expected, next);
}

// A writer and a reader: every read is whole, none is older than the one before, and once the
// writer is done the reader gets its last value.
TEST(Handoff, TripleBufferAcrossThreadsIsWholeMonotoneAndEndsOnTheNewest) {
  TripleBuffer<Stamped> buffer;
  constexpr std::uint64_t kLast = 100000;
  std::thread writer([&] {
    std::mt19937 pace(kSeed);
    for (std::uint64_t i = 1; i <= kLast; ++i) {
      buffer.write(stamped(i));
      if (pace() % 64 == 0) std::this_thread::yield();
    }
  });
  std::uint64_t last = 0, reads = 0, fresh = 0;
  bool torn = false, backwards = false, staleFresh = false;
  std::mt19937 pace(kSeed + 1);
  while (last < kLast) {
    bool isNew = false;
    const Stamped s = buffer.read(&isNew);
    torn |= !whole(s);
    backwards |= s.seq < last;
    staleFresh |= isNew && s.seq == last;  // "new" is never the value read before
    fresh += isNew ? 1 : 0;
    last = s.seq;
    ++reads;
    if (pace() % 64 == 0) std::this_thread::yield();
  }
  writer.join();
  EXPECT_FALSE(torn);
  EXPECT_FALSE(backwards);
  EXPECT_FALSE(staleFresh);
  EXPECT_GT(fresh, 0u);
  bool isNew = true;
  EXPECT_EQ(buffer.read(&isNew).seq, kLast);
  EXPECT_FALSE(isNew);
}

// A producer and a consumer on a small ring (so it fills and wraps often): every value arrives,
// whole, exactly once and in order.
TEST(Handoff, RingAcrossThreadsDeliversEveryValueInOrder) {
  SpscRing<Stamped, 64> ring;
  constexpr std::uint64_t kCount = 100000;
  std::uint64_t refused = 0;
  std::thread producer([&] {
    std::mt19937 pace(kSeed + 2);
    for (std::uint64_t i = 1; i <= kCount;) {
      // Bursts of random length, so the ring is sometimes empty and sometimes full.
      const std::uint64_t burst = pace() % 100;
      for (std::uint64_t b = 0; b < burst && i <= kCount; ++b) {
        if (ring.push(stamped(i))) {
          ++i;
        } else {
          ++refused;
          std::this_thread::yield();
        }
      }
      std::this_thread::yield();
    }
  });
  std::uint64_t expected = 1, outOfOrder = 0, torn = 0;
  std::mt19937 pace(kSeed + 3);
  Stamped s;
  while (expected <= kCount) {
    if (!ring.pop(s)) {
      std::this_thread::yield();
      continue;
    }
    outOfOrder += s.seq != expected ? 1 : 0;
    torn += whole(s) ? 0u : 1u;
    expected = s.seq + 1;
    if (pace() % 128 == 0) std::this_thread::yield();
  }
  producer.join();
  EXPECT_EQ(outOfOrder, 0u);
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(expected, kCount + 1);
  EXPECT_FALSE(ring.pop(s));  // nothing left over, nothing delivered twice
  RecordProperty("refused_pushes", std::to_string(refused));
}

}  // namespace
}  // namespace osteon::core
