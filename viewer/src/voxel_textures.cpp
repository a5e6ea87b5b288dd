#include "voxel_textures.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace osteon::viewer {

namespace {

std::size_t boxVoxels(const glm::ivec3& lo, const glm::ivec3& hi) {
  const glm::ivec3 n = hi - lo + 1;
  return std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z);
}

}  // namespace

std::string VoxelTextures::reset(const geometry::VoxelGrid& grid) {
  levels_.reset();
  density_.reset();
  available_ = false;
  refined_.clear();
  boxLo_ = glm::ivec3(0);
  boxHi_ = glm::ivec3(-1);
  dims_ = grid.dims();
  originMm_ = grid.originMm();
  voxelMm_ = grid.voxelSizeMm();
  brickDims_ = grid.brickDims();
  GLint maxSide = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &maxSide);
  if (grid.voxelCount() > kMaxVoxels || dims_.x > maxSide || dims_.y > maxSide ||
      dims_.z > maxSide) {
    return "the grid is too large for the level and density textures";
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  levels_ = GlTexture(newTexture());
  configureTexture3D(levels_.get(), GL_NEAREST);
  levelStaging_.assign(grid.voxelCount(), 0);
  glTexImage3D(GL_TEXTURE_3D, 0, GL_R8I, dims_.x, dims_.y, dims_.z, 0, GL_RED_INTEGER, GL_BYTE,
               levelStaging_.data());
  levelStaging_.clear();

  density_ = GlTexture(newTexture());
  configureTexture3D(density_.get(), GL_NEAREST);
  glTexImage3D(GL_TEXTURE_3D, 0, GL_R16I, dims_.x, dims_.y, dims_.z, 0, GL_RED_INTEGER, GL_SHORT,
               nullptr);
  updateDensityBox(grid, glm::ivec3(0), dims_ - 1);
  // The colour ramp's ends: the smallest and largest positive density as loaded.
  int low = std::numeric_limits<int>::max(), high = 0;
  for (const std::int16_t d : densityStaging_) {
    if (d > 0) low = std::min(low, int(d)), high = std::max(high, int(d));
  }
  densityLow_ = high > 0 ? low : 0;
  densityHigh_ = std::max(high, densityLow_ + 1);
  densityStaging_.clear();
  densityStaging_.shrink_to_fit();
  glBindTexture(GL_TEXTURE_3D, 0);
  available_ = true;
  return "";
}

void VoxelTextures::updateLevels(const glm::ivec3* refined, std::size_t count, int depth) {
  if (!available_) return;
  if (depth == depth_ && count == refined_.size() &&
      (count == 0 || std::memcmp(refined, refined_.data(), count * sizeof(glm::ivec3)) == 0)) {
    return;
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glBindTexture(GL_TEXTURE_3D, levels_.get());
  // Clear the old box, then write the new one.
  if (glm::all(glm::greaterThanEqual(boxHi_, boxLo_))) {
    levelStaging_.assign(boxVoxels(boxLo_, boxHi_), 0);
    const glm::ivec3 n = boxHi_ - boxLo_ + 1;
    glTexSubImage3D(GL_TEXTURE_3D, 0, boxLo_.x, boxLo_.y, boxLo_.z, n.x, n.y, n.z, GL_RED_INTEGER,
                    GL_BYTE, levelStaging_.data());
  }
  refined_.assign(refined, refined + count);
  depth_ = depth;
  boxLo_ = dims_;
  boxHi_ = glm::ivec3(-1);
  for (const glm::ivec3& v : refined_) {
    if (!glm::all(glm::greaterThanEqual(v, glm::ivec3(0))) || !glm::all(glm::lessThan(v, dims_)))
      continue;
    boxLo_ = glm::min(boxLo_, v);
    boxHi_ = glm::max(boxHi_, v);
  }
  if (glm::all(glm::greaterThanEqual(boxHi_, boxLo_))) {
    levelStaging_.assign(boxVoxels(boxLo_, boxHi_), 0);
    const glm::ivec3 n = boxHi_ - boxLo_ + 1;
    for (const glm::ivec3& v : refined_) {
      if (!glm::all(glm::greaterThanEqual(v, boxLo_)) || !glm::all(glm::lessThanEqual(v, boxHi_)))
        continue;
      const glm::ivec3 l = v - boxLo_;
      levelStaging_[std::size_t(l.x) +
                    std::size_t(n.x) * (std::size_t(l.y) + std::size_t(n.y) * std::size_t(l.z))] =
          std::int8_t(-depth);
    }
    glTexSubImage3D(GL_TEXTURE_3D, 0, boxLo_.x, boxLo_.y, boxLo_.z, n.x, n.y, n.z, GL_RED_INTEGER,
                    GL_BYTE, levelStaging_.data());
  }
  glBindTexture(GL_TEXTURE_3D, 0);
}

void VoxelTextures::updateDensityBox(const geometry::VoxelGrid& grid, glm::ivec3 lo,
                                     glm::ivec3 hi) {
  if (!density_.get()) return;
  lo = glm::max(lo, glm::ivec3(0));
  hi = glm::min(hi, dims_ - 1);
  if (!glm::all(glm::greaterThanEqual(hi, lo))) return;
  densityStaging_.resize(boxVoxels(lo, hi));
  std::size_t i = 0;
  for (int z = lo.z; z <= hi.z; ++z) {
    for (int y = lo.y; y <= hi.y; ++y) {
      for (int x = lo.x; x <= hi.x; ++x) densityStaging_[i++] = grid.density({x, y, z});
    }
  }
  const glm::ivec3 n = hi - lo + 1;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glBindTexture(GL_TEXTURE_3D, density_.get());
  glTexSubImage3D(GL_TEXTURE_3D, 0, lo.x, lo.y, lo.z, n.x, n.y, n.z, GL_RED_INTEGER, GL_SHORT,
                  densityStaging_.data());
  glBindTexture(GL_TEXTURE_3D, 0);
}

void VoxelTextures::updateDensity(const geometry::VoxelGrid& grid,
                                  const geometry::SurfaceDelta& delta) {
  if (!available_ || delta.everything) return;
  // Cell brick keys: (cb.x + 1) + (nb.x + 1) ((cb.y + 1) + (nb.y + 1) (cb.z + 1)); its cells
  // 8 cb .. 8 cb + 7 read voxels 8 cb .. 8 cb + 8.
  const std::int64_t nx = brickDims_.x + 1, ny = brickDims_.y + 1;
  for (const geometry::SurfaceDelta::Brick& b : delta.bricks) {
    const glm::ivec3 cb(int(b.key % nx) - 1, int((b.key / nx) % ny) - 1,
                        int(b.key / (nx * ny)) - 1);
    const glm::ivec3 lo = cb * geometry::VoxelGrid::kBrickSize;
    updateDensityBox(grid, lo, lo + geometry::VoxelGrid::kBrickSize);
  }
}

void VoxelTextures::bind(GLuint program) const {
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_3D, levels_.get());
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_3D, density_.get());
  glActiveTexture(GL_TEXTURE0);
  setUniform(program, "uLevels", 0);
  setUniform(program, "uDensity", 1);
  setUniform(program, "uDims", glm::max(dims_, glm::ivec3(1)));
  setUniform(program, "uGridOrigin", glm::vec3(originMm_));
  setUniform(program, "uVoxelMm", float(voxelMm_));
  setUniform(program, "uDensityRange", glm::vec3(float(densityLow_), float(densityHigh_), 0.0f));
}

}  // namespace osteon::viewer
