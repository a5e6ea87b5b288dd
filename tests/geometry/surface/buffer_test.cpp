// Buffer<T>: std::vector semantics with default-initialising resize, and large arrays on
// 2 MiB boundaries kept for reuse when freed.
#include "osteon/geometry/surface/buffer.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <numeric>
#include <thread>
#include <vector>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

namespace osteon::geometry {
namespace {

TEST(Buffer, KeepsValuesAcrossGrowthPastTheLargeSize) {
  Buffer<std::uint32_t> b(1000);
  std::iota(b.begin(), b.end(), 7u);
  // 3 M elements of 4 bytes: 12 MiB, past the 1 MiB large-array size.
  b.resize(std::size_t(3) << 20);
  for (std::uint32_t i = 0; i < 1000; ++i) ASSERT_EQ(b[i], 7u + i);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % (std::size_t(2) << 20), 0u);
  b.back() = 42u;
  b.resize(10);  // shrinking keeps the block; the first elements stay
  EXPECT_EQ(b[9], 16u);
  b.shrink_to_fit();  // back to a small block
  EXPECT_EQ(b.size(), 10u);
  EXPECT_EQ(b[0], 7u);
}

TEST(Buffer, ValueArgumentsStillInitialise) {
  Buffer<glm::dvec3> b(5, glm::dvec3(1.0, 2.0, 3.0));
  b.resize(8, glm::dvec3(-1.0));
  EXPECT_EQ(b[4], glm::dvec3(1.0, 2.0, 3.0));
  EXPECT_EQ(b[7], glm::dvec3(-1.0));
  b.assign(3, glm::dvec3(0.5));
  EXPECT_EQ(b.size(), 3u);
  EXPECT_EQ(b[2], glm::dvec3(0.5));
  const Buffer<glm::dvec3> copy = b;
  EXPECT_EQ(copy, b);
}

TEST(Buffer, AFreedLargeArrayServesTheNextOfItsSizeUntilReleased) {
  releaseCachedBuffers();
  ASSERT_EQ(cachedBufferBytes(), 0u);
  const std::size_t n = std::size_t(3) << 20;  // 24 MiB of uint64: a 24 MiB block
  const std::uint64_t* first = nullptr;
  {
    Buffer<std::uint64_t> a(n);
    a.back() = 7u;
    first = a.data();
  }
  EXPECT_EQ(cachedBufferBytes(), std::size_t(24) << 20);
  {
    Buffer<std::uint64_t> small(std::size_t(1) << 18);  // 2 MiB: another size, a fresh block
    EXPECT_NE(small.data(), first);
    Buffer<std::uint64_t> b(n - 1000);  // the same 2 MiB steps: the freed block again
    EXPECT_EQ(b.data(), first);
    EXPECT_EQ(cachedBufferBytes(), 0u);
    b.back() = 9u;  // writable
  }
  EXPECT_EQ(cachedBufferBytes(), std::size_t(26) << 20);
  releaseCachedBuffers();
  EXPECT_EQ(cachedBufferBytes(), 0u);
}

TEST(Buffer, TheCacheKeepsItsBoundsAndGivesBackTheOldestFirst) {
  constexpr std::size_t kMiB = std::size_t(1) << 20;
  releaseCachedBuffers();
  {
    // A 4 MiB array freed first, then eight of 2 MiB: the ninth block pushes out the oldest.
    Buffer<std::uint8_t> first(3 * kMiB);
    first.clear();
    first.shrink_to_fit();  // freed now, before the others
    std::vector<Buffer<std::uint8_t>> arrays;
    for (std::size_t i = 0; i < kCachedBufferBlocks; ++i) arrays.emplace_back(kMiB + 1);
  }
  EXPECT_EQ(cachedBufferBytes(), kCachedBufferBlocks * 2 * kMiB);  // the 4 MiB block went
  {
    // A 40 MiB and a 30 MiB array cannot both stay (70 MiB). Freed in reverse order, the
    // 30 MiB one goes in first (the oldest 2 MiB block gives way to it, for the count); the
    // 40 MiB one then pushes out every older block, the 30 MiB one included.
    Buffer<std::uint8_t> big(40 * kMiB), bigger(30 * kMiB);
  }
  EXPECT_EQ(cachedBufferBytes(), 40 * kMiB);
  {
    Buffer<std::uint8_t> again(39 * kMiB + 1);  // rounds to 40 MiB: taken from the cache
    EXPECT_EQ(cachedBufferBytes(), 0u);
    std::fill(again.begin(), again.end(), std::uint8_t(0xab));  // the whole block is writable
    EXPECT_EQ(again[12345], 0xab);
  }
  {
    Buffer<std::uint8_t> largest(kCachedBufferBytes);  // 64 MiB: the largest block kept
  }
  EXPECT_EQ(cachedBufferBytes(), kCachedBufferBytes);
  {
    Buffer<std::uint8_t> huge(kCachedBufferBytes + 1);  // rounds to 66 MiB: given back at once
  }
  EXPECT_EQ(cachedBufferBytes(), kCachedBufferBytes);
  releaseCachedBuffers();
  EXPECT_EQ(cachedBufferBytes(), 0u);
}

TEST(Buffer, TheLargeSizeCountsBytesNotElements) {
  releaseCachedBuffers();
  // 24-byte elements: 43,690 of them are just under 1 MiB, 43,691 just over.
  const std::size_t below = (std::size_t(1) << 20) / sizeof(glm::dvec3);
  { Buffer<glm::dvec3> b(below); }
  EXPECT_EQ(cachedBufferBytes(), 0u);
  { Buffer<glm::dvec3> b(below + 1); }
  EXPECT_EQ(cachedBufferBytes(), std::size_t(2) << 20);
  releaseCachedBuffers();
}

TEST(Buffer, ThreadsTakeAndGiveBackLargeArraysTogether) {
  releaseCachedBuffers();
  std::vector<std::thread> threads;
  std::atomic<int> wrong{0};
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([t, &wrong] {
      for (int i = 0; i < 200; ++i) {
        Buffer<std::uint32_t> b((std::size_t(1 + (i + t) % 5) << 18) + 7);  // 1-5 MiB
        std::fill(b.begin(), b.end(), std::uint32_t(t * 1000 + i));
        if (b.front() != std::uint32_t(t * 1000 + i) || b.back() != std::uint32_t(t * 1000 + i))
          ++wrong;
        if (i % 50 == 49) releaseCachedBuffers();
      }
    });
  }
  for (std::thread& th : threads) th.join();
  EXPECT_EQ(wrong.load(), 0);
  EXPECT_LE(cachedBufferBytes(), kCachedBufferBytes);
  releaseCachedBuffers();
  EXPECT_EQ(cachedBufferBytes(), 0u);
}

}  // namespace
}  // namespace osteon::geometry
