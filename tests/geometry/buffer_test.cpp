// Buffer<T>: std::vector semantics with default-initialising resize, and large arrays on
// 2 MiB boundaries kept for reuse when freed.
#include "osteon/geometry/buffer.h"

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <vector>

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
  releaseCachedBuffers();
  {
    // Nine 2 MiB arrays freed: one more than the cache holds.
    std::vector<Buffer<std::uint8_t>> arrays;
    for (std::size_t i = 0; i < kCachedBufferBlocks + 1; ++i) arrays.emplace_back(std::size_t(3) << 19);
  }
  EXPECT_EQ(cachedBufferBytes(), kCachedBufferBlocks * (std::size_t(2) << 20));
  {
    // Past the byte bound: a 40 MiB and a 30 MiB array (70 MiB) cannot both stay.
    Buffer<std::uint8_t> big(std::size_t(40) << 20), bigger(std::size_t(30) << 20);
  }
  EXPECT_LE(cachedBufferBytes(), kCachedBufferBytes);
  EXPECT_GE(cachedBufferBytes(), std::size_t(30) << 20);
  {
    Buffer<std::uint8_t> huge(kCachedBufferBytes + 1);  // larger than the cache: given back at once
  }
  EXPECT_LE(cachedBufferBytes(), kCachedBufferBytes);
  releaseCachedBuffers();
  EXPECT_EQ(cachedBufferBytes(), 0u);
}

}  // namespace
}  // namespace osteon::geometry
