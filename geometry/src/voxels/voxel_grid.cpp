#include "osteon/geometry/voxels/voxel_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "osteon/core/assert.h"

namespace osteon::geometry {

VoxelGrid::VoxelGrid(glm::ivec3 dims, glm::dvec3 originMm, double voxelSizeMm)
    : dims_(dims), originMm_(originMm), voxelSizeMm_(voxelSizeMm) {
  if (dims.x <= 0 || dims.y <= 0 || dims.z <= 0) {
    throw std::invalid_argument("VoxelGrid: dimensions must be positive");
  }
  if (!std::isfinite(voxelSizeMm) || voxelSizeMm <= 0.0) {
    throw std::invalid_argument("VoxelGrid: voxel size must be positive and finite");
  }
  // Bound the brick table, not only the voxels: a thin grid pads every brick to 8^3.
  std::uint64_t bricks = 1;
  for (int c = 0; c < 3; ++c) {
    bricks *= (std::uint64_t(dims[c]) + kBrickSize - 1) / kBrickSize;
  }
  if (voxelCount() > kMaxVoxels || bricks > kMaxVoxels / kBrickVoxels) {
    throw std::invalid_argument("VoxelGrid: more than 2^32 voxels (bricks included)");
  }
  brickDims_ = (dims + (kBrickSize - 1)) / kBrickSize;  // no overflow: each dim < 2^32 / 1
  const std::size_t n = std::size_t(bricks);
  bricks_.resize(n);
  uniformFill_.assign(n, 0);
  uniformDensity_.assign(n, 0);
  dirty_.assign(n, 0);
}

VoxelGrid::VoxelGrid(const VoxelGrid& other)
    : dims_(other.dims_),
      brickDims_(other.brickDims_),
      originMm_(other.originMm_),
      voxelSizeMm_(other.voxelSizeMm_),
      uniformFill_(other.uniformFill_),
      uniformDensity_(other.uniformDensity_),
      dirty_(other.dirty_) {
  bricks_.resize(other.bricks_.size());
  for (std::size_t i = 0; i < bricks_.size(); ++i) {
    if (other.bricks_[i]) bricks_[i] = std::make_unique<Brick>(*other.bricks_[i]);
  }
}

VoxelGrid& VoxelGrid::operator=(const VoxelGrid& other) {
  if (this != &other) *this = VoxelGrid(other);
  return *this;
}

std::uint64_t VoxelGrid::voxelCount() const {
  return std::uint64_t(dims_.x) * std::uint64_t(dims_.y) * std::uint64_t(dims_.z);
}

glm::ivec3 VoxelGrid::voxelFromWorld(const glm::dvec3& pMm) const {
  return glm::ivec3(glm::floor(gridFromWorld(pMm)));
}

glm::ivec3 VoxelGrid::brickCoord(std::size_t brick) const {
  const std::size_t nx = std::size_t(brickDims_.x);
  const std::size_t ny = std::size_t(brickDims_.y);
  return glm::ivec3(int(brick % nx), int((brick / nx) % ny), int(brick / (nx * ny)));
}

Fill VoxelGrid::fill(const glm::ivec3& ijk) const {
  std::size_t brick;
  int local;
  if (!locate(ijk, brick, local)) return 0;
  const Brick* b = bricks_[brick].get();
  return b ? b->fill[std::size_t(local)] : uniformFill_[brick];
}

Density VoxelGrid::density(const glm::ivec3& ijk) const {
  std::size_t brick;
  int local;
  if (!locate(ijk, brick, local)) return 0;
  const Brick* b = bricks_[brick].get();
  return b ? b->density[std::size_t(local)] : uniformDensity_[brick];
}

void VoxelGrid::set(const glm::ivec3& ijk, Fill fill, Density density) {
  std::size_t brick;
  int local;
  if (!locate(ijk, brick, local)) throw std::out_of_range("VoxelGrid::set outside the grid");
  Brick* b = bricks_[brick].get();
  if (!b) {
    if (uniformFill_[brick] == fill && uniformDensity_[brick] == density) return;
    if (!spare_.empty()) {
      bricks_[brick] = std::move(spare_.back());
      spare_.pop_back();
      bricks_[brick]->fill.fill(uniformFill_[brick]);
      bricks_[brick]->density.fill(uniformDensity_[brick]);
    } else if (spare_.capacity() > 0) {
      ++spareMisses_;
    }
    b = &materialiseBrick(brick);
  }
  // Dirty means "the surface may have changed": fill, not density (a drilling step lowers
  // the density of every voxel under the tool but removes few).
  if (b->fill[std::size_t(local)] != fill) dirty_[brick] = 1;
  b->fill[std::size_t(local)] = fill;
  b->density[std::size_t(local)] = density;
}

void VoxelGrid::reserveSpareBricks(std::size_t count) {
  spare_.reserve(spare_.size() + count);
  while (spare_.size() < spare_.capacity()) spare_.push_back(std::make_unique<Brick>());
}

void VoxelGrid::release(std::size_t brick) {
  if (bricks_[brick] && spare_.size() < spare_.capacity()) {
    spare_.push_back(std::move(bricks_[brick]));  // within capacity: no allocation
  }
  bricks_[brick].reset();
}

void VoxelGrid::setBrickUniform(std::size_t brick, Fill fill, Density density) {
  release(brick);
  uniformFill_[brick] = fill;
  uniformDensity_[brick] = density;
  dirty_[brick] = 1;
}

VoxelGrid::Brick& VoxelGrid::materialiseBrick(std::size_t brick) {
  OSTEON_ASSERT(brick < bricks_.size(), "a brick of this grid");
  if (!bricks_[brick]) {
    auto b = std::make_unique<Brick>();
    b->fill.fill(uniformFill_[brick]);
    b->density.fill(uniformDensity_[brick]);
    bricks_[brick] = std::move(b);
  }
  return *bricks_[brick];
}

std::size_t VoxelGrid::compact() {
  std::size_t freed = 0;
  for (std::size_t i = 0; i < bricks_.size(); ++i) {
    const Brick* b = bricks_[i].get();
    if (!b) continue;
    // Only voxels inside the grid count: an edge brick's padding is never read.
    const glm::ivec3 lo = brickCoord(i) * kBrickSize;
    const glm::ivec3 span = glm::min(lo + kBrickSize, dims_) - lo;
    const Fill f = b->fill[0];
    const Density d = b->density[0];
    bool uniform = true;
    for (int z = 0; z < span.z && uniform; ++z)
      for (int y = 0; y < span.y && uniform; ++y)
        for (int x = 0; x < span.x && uniform; ++x) {
          const std::size_t k = std::size_t(voxelInBrick({x, y, z}));
          uniform = b->fill[k] == f && b->density[k] == d;
        }
    if (!uniform) continue;
    // Same voxel values: the brick's dirty state is left as it was.
    release(i);
    uniformFill_[i] = f;
    uniformDensity_[i] = d;
    ++freed;
  }
  return freed;
}

std::size_t VoxelGrid::allocatedBrickCount() const {
  return std::size_t(std::count_if(bricks_.begin(), bricks_.end(),
                                   [](const std::unique_ptr<Brick>& b) { return b != nullptr; }));
}

std::vector<std::size_t> VoxelGrid::dirtyBricks() const {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < dirty_.size(); ++i) {
    if (dirty_[i]) out.push_back(i);
  }
  return out;
}

void VoxelGrid::clearDirty() {
  std::fill(dirty_.begin(), dirty_.end(), std::uint8_t(0));
}

namespace {

// Number of voxels of brick `b` that lie inside the grid (edge bricks are partial).
std::uint64_t voxelsInBrick(const glm::ivec3& brickCoord, const glm::ivec3& dims) {
  const glm::ivec3 lo = brickCoord * VoxelGrid::kBrickSize;
  const glm::ivec3 hi = glm::min(lo + VoxelGrid::kBrickSize, dims);
  return std::uint64_t(hi.x - lo.x) * std::uint64_t(hi.y - lo.y) * std::uint64_t(hi.z - lo.z);
}

}  // namespace

namespace {

// fn(fill, voxels) over the grid: each stored brick's voxels one by one (voxels 1), each uniform
// brick once with its voxel count inside the grid.
template <typename Fn>
void forEachFill(const VoxelGrid& grid, Fn&& fn) {
  for (std::size_t i = 0; i < grid.brickCount(); ++i) {
    const glm::ivec3 bc = grid.brickCoord(i);
    if (const VoxelGrid::Brick* b = grid.brickData(i)) {
      const glm::ivec3 lo = bc * VoxelGrid::kBrickSize;
      const glm::ivec3 hi = glm::min(lo + VoxelGrid::kBrickSize, grid.dims()) - lo;
      for (int z = 0; z < hi.z; ++z)
        for (int y = 0; y < hi.y; ++y)
          for (int x = 0; x < hi.x; ++x)
            fn(b->fill[std::size_t(VoxelGrid::voxelInBrick({x, y, z}))], std::uint64_t(1));
    } else {
      fn(grid.brickUniformFill(i), voxelsInBrick(bc, grid.dims()));
    }
  }
}

}  // namespace

std::uint64_t VoxelGrid::countVoxels(Fill minFill) const {
  std::uint64_t count = 0;
  forEachFill(*this,
              [&](Fill fill, std::uint64_t voxels) { count += fill >= minFill ? voxels : 0u; });
  return count;
}

std::uint64_t VoxelGrid::totalFill() const {
  std::uint64_t total = 0;
  forEachFill(*this,
              [&](Fill fill, std::uint64_t voxels) { total += std::uint64_t(fill) * voxels; });
  return total;
}

double VoxelGrid::filledVolumeMm3() const {
  return double(totalFill()) / double(kFillFull) * voxelVolumeMm3();
}

std::size_t VoxelGrid::memoryBytes() const {
  const std::size_t perSlot =
      sizeof(std::unique_ptr<Brick>) + sizeof(Fill) + sizeof(Density) + sizeof(std::uint8_t);
  return sizeof(*this) + bricks_.size() * perSlot + allocatedBrickCount() * sizeof(Brick) +
         spare_.capacity() * sizeof(std::unique_ptr<Brick>) + spare_.size() * sizeof(Brick);
}

}  // namespace osteon::geometry
