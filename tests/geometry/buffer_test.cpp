// Buffer<T>: std::vector semantics with default-initialising resize and large arrays on
// 2 MiB boundaries.
#include "osteon/geometry/buffer.h"

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>

namespace osteon::geometry {
namespace {

TEST(Buffer, KeepsValuesAcrossGrowthPastTheLargeSize) {
  Buffer<std::uint32_t> b(1000);
  std::iota(b.begin(), b.end(), 7u);
  // 3 M elements of 4 bytes: 12 MiB, past the 8 MiB large-array size.
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

}  // namespace
}  // namespace osteon::geometry
