// Per-voxel values for the level and density views: two integer 3-D textures over the grid
// that the bone shader reads at the voxel under each vertex (half a voxel inside along its
// normal, so a vertex between a bone voxel and an empty one reads the bone's). Only what changed
// is uploaded: the refined voxels' boxes (old cleared, new written) for levels, the voxels of
// changed cell bricks for density.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gl_util.h"
#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::viewer {

class VoxelTextures {
 public:
  // Grids larger than this many voxels get no textures (the views say so).
  static constexpr std::uint64_t kMaxVoxels = std::uint64_t(64) << 20;

  // New textures for a new grid: density from it, every level 0. Returns "" or why the views
  // are unavailable (too large a grid).
  std::string reset(const geometry::VoxelGrid& grid);
  bool available() const { return available_; }

  // The refined voxels now (DisplayState::refined, all at `depth`); uploads when they changed.
  void updateLevels(const glm::ivec3* refined, std::size_t count, int depth);
  // The density of the voxels that the changed cell bricks read, from the (visual) grid.
  void updateDensity(const geometry::VoxelGrid& grid, const geometry::SurfaceDelta& delta);
  // The density of every voxel in [lo, hi] (voxel indices, clamped to the grid).
  void updateDensityBox(const geometry::VoxelGrid& grid, glm::ivec3 lo, glm::ivec3 hi);

  // The density ramp's ends: the smallest and largest positive density as loaded.
  int densityLow() const { return densityLow_; }
  int densityHigh() const { return densityHigh_; }
  // Binds the textures to units 0 (levels) and 1 (density) and sets the shader's uniforms.
  void bind(GLuint program) const;

 private:
  GlTexture levels_, density_;
  bool available_ = false;
  glm::ivec3 dims_{0};
  glm::dvec3 originMm_{0.0};
  double voxelMm_ = 1.0;
  glm::ivec3 brickDims_{0};
  int densityLow_ = 0, densityHigh_ = 1;
  // The refined voxels last uploaded and their box (empty when hi < lo).
  std::vector<glm::ivec3> refined_;
  int depth_ = 0;
  glm::ivec3 boxLo_{0}, boxHi_{-1};
  std::vector<std::int8_t> levelStaging_;
  std::vector<std::int16_t> densityStaging_;
};

}  // namespace osteon::viewer
