// The level -2 fills a refined voxel starts from (refinement, seed 3.5): where the source mesh
// is known, every voxel the surface passes through is sampled once at a quarter of the voxel
// size, so refining at run time casts no rays and only copies.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

class EmbreeScene;

inline constexpr int kMaxRefineDepth = 2;
inline constexpr int kSubPerEdge = 1 << kMaxRefineDepth;  // level -2 sub-voxels per edge
inline constexpr int kSubVoxels = kSubPerEdge * kSubPerEdge * kSubPerEdge;  // 64

// Level -2 fill of every voxel the surface passes through (0 < fill < full), sampled from the
// mesh once and fitted to sum exactly to the voxel's fill, so refining at run time casts no
// rays and only copies. In fill units: a full level -2 sub-voxel holds 255.
class FineFillSource {
 public:
  FineFillSource() = default;
  // raysPerSubAxis^2 rays along z through each level -2 sub-column of every partial voxel.
  static FineFillSource sample(const VoxelGrid& grid, const TriangleMesh& mesh,
                               const EmbreeScene& surface, int raysPerSubAxis = 2);
  // The 64 sub-voxel fills of voxel v (x fastest) and v's fill when sampled; false for a
  // voxel that was empty or full then.
  bool find(const glm::ivec3& v, std::array<std::uint8_t, kSubVoxels>& subFill,
            Fill& sampledFill) const;
  std::size_t voxelCount() const { return keys_.size(); }
  std::size_t memoryBytes() const;

 private:
  glm::ivec3 dims_{0};
  std::vector<std::uint64_t> keys_;  // sorted grid linear indices
  std::vector<std::array<std::uint8_t, kSubVoxels>> subFill_;
  std::vector<Fill> sampledFill_;
};

}  // namespace osteon::geometry
