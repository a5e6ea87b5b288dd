// The bone volume: a regular grid of voxels stored sparsely in 8^3 bricks (OpenVDB's lesson).
// A brick whose voxels all hold one value (outside the bone, or deep in cancellous bone)
// costs a few bytes; only bricks the surface passes through, or that drilling has touched,
// hold per-voxel arrays. Which bricks changed is a first-class fact (dirty flags) for the
// incremental surface update.
//
// Coordinates: grid space is continuous voxel units, voxel (i, j, k) covering [i, i+1) x
// [j, j+1) x [k, k+1); world space is millimetres, worldFromGrid(g) = originMm + g * size.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "osteon/core/constants.h"

namespace osteon::geometry {

// Bone volume inside a voxel, in units of 1/16320 of the voxel (0 empty, 16320 full).
// 16320 = 255 x 64: the voxelizer's 1/255 steps are multiples of 64 units, and the 8 or 64
// sub-voxels of a refined voxel (levels -1, -2) count volume in the same absolute units, so
// a parent's fill is exactly the sum of its children's and refinement never loses volume.
using Fill = std::uint16_t;
using Density = std::int16_t;  // seed 3.5: integer drilling difficulty d (0 where no bone)

inline constexpr Fill kFillFull = 16320;
inline constexpr Fill kFillHalf = 8160;   // a voxel is "inside" at or above half full
inline constexpr Fill kFillPerStep = 64;  // one 1/255 step of the voxelizer
inline constexpr int kFillSteps = 255;    // kFillFull / kFillPerStep

class VoxelGrid {
 public:
  static constexpr int kBrickLog2 = osteon::kBrickLog2;
  static constexpr int kBrickSize = kBrickEdge;  // voxels per brick edge
  static constexpr int kBrickVoxels = osteon::kBrickVoxels;
  // Grids above this many voxels, counting the padding of edge bricks, are refused (the brick
  // table alone would pass 100 MB).
  static constexpr std::uint64_t kMaxVoxels = std::uint64_t(1) << 32;

  struct Brick {
    std::array<Fill, kBrickVoxels> fill;  // x fastest, then y, then z
    std::array<Density, kBrickVoxels> density;
  };

  VoxelGrid() = default;
  // Throws std::invalid_argument for non-positive dims or size, or too many voxels.
  VoxelGrid(glm::ivec3 dims, glm::dvec3 originMm, double voxelSizeMm);
  // Copies are deep (every allocated brick is duplicated); moves are cheap.
  VoxelGrid(const VoxelGrid& other);
  VoxelGrid& operator=(const VoxelGrid& other);
  VoxelGrid(VoxelGrid&&) noexcept = default;
  VoxelGrid& operator=(VoxelGrid&&) noexcept = default;

  glm::ivec3 dims() const { return dims_; }
  glm::dvec3 originMm() const { return originMm_; }  // corner of voxel (0, 0, 0)
  double voxelSizeMm() const { return voxelSizeMm_; }
  double voxelVolumeMm3() const { return voxelSizeMm_ * voxelSizeMm_ * voxelSizeMm_; }
  std::uint64_t voxelCount() const;

  // Transforms (named "to from from", as pbrt does).
  glm::dvec3 worldFromGrid(const glm::dvec3& g) const { return originMm_ + g * voxelSizeMm_; }
  glm::dvec3 gridFromWorld(const glm::dvec3& pMm) const { return (pMm - originMm_) / voxelSizeMm_; }
  glm::dvec3 voxelCentreMm(const glm::ivec3& ijk) const {
    return worldFromGrid(glm::dvec3(ijk) + 0.5);
  }
  glm::ivec3 voxelFromWorld(const glm::dvec3& pMm) const;  // floor; may lie outside
  bool inBounds(const glm::ivec3& ijk) const {
    return ijk.x >= 0 && ijk.y >= 0 && ijk.z >= 0 && ijk.x < dims_.x && ijk.y < dims_.y &&
           ijk.z < dims_.z;
  }

  // Per-voxel access; outside the grid reads as empty.
  Fill fill(const glm::ivec3& ijk) const;
  Density density(const glm::ivec3& ijk) const;
  // Both at once: one brick look-up (the haptic step reads both for every voxel it visits).
  void fillAndDensity(const glm::ivec3& ijk, Fill& fill, Density& density) const;
  // Writes materialise the brick when the value breaks its uniformity, and mark it dirty when
  // the fill changes (dirty: the surface there may have changed; density alone does not).
  // One writer at a time (parallel writers use materialiseBrick on distinct bricks). A brick
  // set() materialises comes from the spare pool while it lasts, so a real-time writer does
  // not allocate.
  void set(const glm::ivec3& ijk, Fill fill, Density density);
  // Allocates `count` spare bricks up front for set(); bricks freed by setBrickUniform and
  // compact return to the pool while it has room.
  void reserveSpareBricks(std::size_t count);
  std::size_t spareBricks() const { return spare_.size(); }
  // Bricks set() had to allocate because the reserved pool was empty.
  std::uint64_t spareMisses() const { return spareMisses_; }

  // Bricks.
  glm::ivec3 brickDims() const { return brickDims_; }
  std::size_t brickCount() const { return uniformFill_.size(); }
  std::size_t brickIndex(const glm::ivec3& brickCoord) const {
    return std::size_t(brickCoord.x) +
           std::size_t(brickDims_.x) *
               (std::size_t(brickCoord.y) + std::size_t(brickDims_.y) * std::size_t(brickCoord.z));
  }
  glm::ivec3 brickCoord(std::size_t brick) const;
  static int voxelInBrick(const glm::ivec3& local) {
    return local.x + kBrickSize * (local.y + kBrickSize * local.z);
  }
  bool brickAllocated(std::size_t brick) const { return bricks_[brick] != nullptr; }
  const Brick* brickData(std::size_t brick) const { return bricks_[brick].get(); }
  // Value of every voxel of a brick that is not allocated.
  Fill brickUniformFill(std::size_t brick) const { return uniformFill_[brick]; }
  Density brickUniformDensity(std::size_t brick) const { return uniformDensity_[brick]; }
  // Frees a brick's arrays and gives all its voxels one value. Marks it dirty.
  void setBrickUniform(std::size_t brick, Fill fill, Density density);
  // Per-voxel arrays of a brick, created from its uniform value when needed (the values do not
  // change, so neither does the dirty flag).
  // Distinct bricks may be materialised from distinct threads at once.
  Brick& materialiseBrick(std::size_t brick);
  // Frees the arrays of allocated bricks whose voxels all agree; returns how many.
  std::size_t compact();
  std::size_t allocatedBrickCount() const;

  // Dirty flags for incremental meshing: bricks whose fill may have changed.
  bool brickDirty(std::size_t brick) const { return dirty_[brick] != 0; }
  void markBrickDirty(std::size_t brick) { dirty_[brick] = 1; }
  void clearBrickDirty(std::size_t brick) { dirty_[brick] = 0; }
  std::vector<std::size_t> dirtyBricks() const;
  void clearDirty();

  // Totals.
  std::uint64_t countVoxels(Fill minFill) const;  // voxels with fill >= minFill
  std::uint64_t totalFill() const;                // sum of fill, exact (removal accounting)
  double filledVolumeMm3() const;                 // totalFill / kFillFull x voxel volume
  std::size_t memoryBytes() const;

 private:
  bool locate(const glm::ivec3& ijk, std::size_t& brick, int& local) const;

  glm::ivec3 dims_{0};
  glm::ivec3 brickDims_{0};
  glm::dvec3 originMm_{0.0};
  double voxelSizeMm_ = 1.0;
  std::vector<std::unique_ptr<Brick>> bricks_;  // null: uniform
  std::vector<Fill> uniformFill_;
  std::vector<Density> uniformDensity_;
  std::vector<std::uint8_t> dirty_;            // bytes, not bits: threads write distinct bricks
  std::vector<std::unique_ptr<Brick>> spare_;  // not copied with the grid
  std::uint64_t spareMisses_ = 0;

  void release(std::size_t brick);  // frees a brick's arrays, into the pool when it has room
};

// Inline: the haptic step reads every level-0 voxel of its shells through these.
inline bool VoxelGrid::locate(const glm::ivec3& ijk, std::size_t& brick, int& local) const {
  if (!inBounds(ijk)) return false;
  brick = brickIndex(ijk >> kBrickLog2);
  local = voxelInBrick(ijk & (kBrickSize - 1));
  return true;
}

inline void VoxelGrid::fillAndDensity(const glm::ivec3& ijk, Fill& fill, Density& density) const {
  std::size_t brick;
  int local;
  if (!locate(ijk, brick, local)) {
    fill = 0;
    density = 0;
    return;
  }
  if (const Brick* b = bricks_[brick].get()) {
    fill = b->fill[std::size_t(local)];
    density = b->density[std::size_t(local)];
  } else {
    fill = uniformFill_[brick];
    density = uniformDensity_[brick];
  }
}

}  // namespace osteon::geometry
