// The hierarchy's build helpers shared by dph.cpp and dph_insertion.cpp: packed voxel keys,
// lattice arithmetic and the permutation of node arrays.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace osteon::geometry::dph_detail {

inline constexpr int kCoordBits = 21;
inline constexpr long long kCoordOffset = 1LL << (kCoordBits - 1);

inline bool packable(const glm::ivec3& v) {
  for (int c = 0; c < 3; ++c) {
    if (v[c] < -kCoordOffset || v[c] >= kCoordOffset) return false;
  }
  return true;
}

inline std::uint64_t packVoxel(const glm::ivec3& v) {
  return (std::uint64_t(v.x + kCoordOffset) << (2 * kCoordBits)) |
         (std::uint64_t(v.y + kCoordOffset) << kCoordBits) | std::uint64_t(v.z + kCoordOffset);
}

inline long long floorDiv(long long a, long long b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

inline long long chebyshev(const glm::ivec3& a, const glm::ivec3& b) {
  const glm::ivec3 d = glm::abs(a - b);
  return std::max({d.x, d.y, d.z});
}

// A permutation applied to a node array: out[i] = in[order[i]].
template <typename T>
void permute(std::vector<T>& values, const std::vector<std::uint32_t>& order) {
  if (values.empty()) return;
  std::vector<T> out(values.size());
  for (std::size_t i = 0; i < order.size(); ++i) out[i] = values[order[i]];
  values.swap(out);
}

}  // namespace osteon::geometry::dph_detail
