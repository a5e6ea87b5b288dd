// The viewer's incremental upload of the live surface (viewer/src/surface_upload.h) into a fake
// GPU: plain arrays whose storage starts poisoned, so a byte the uploader never wrote shows.
// After each of many random drilling (and filling) steps, what the fake GPU would draw must be
// exactly SurfaceUpdater::mesh(): the same triangles, at the same float positions and normals.
#include "surface_upload.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::viewer {
namespace {

using geometry::VoxelGrid;

constexpr std::uint32_t kPoisonIndex = 0xdeadbeefu;

GpuVertex poisonVertex() {
  GpuVertex v;
  for (float& f : v.position) f = 1e30f;
  for (float& f : v.normal) f = 1e30f;
  return v;
}

bool isPoison(const GpuVertex& v) {
  return v.position[0] == 1e30f;
}

// The GPU's two buffers as arrays; every write is checked against the storage's bounds.
class FakeGpu : public SurfaceUploadTarget {
 public:
  std::vector<GpuVertex> vertices;
  std::vector<std::uint32_t> indices;
  std::string outOfBounds;  // the first write past a buffer's storage

  void reallocateVertices(std::size_t capacity, const GpuVertex* data, std::size_t count) override {
    if (count > capacity) note("reallocateVertices", count, capacity);
    vertices.assign(capacity, poisonVertex());
    std::copy(data, data + std::min(count, capacity), vertices.begin());
  }
  void writeVertices(std::size_t first, std::size_t count, const GpuVertex* data) override {
    if (first + count > vertices.size())
      return note("writeVertices", first + count, vertices.size());
    std::copy(data, data + count, vertices.begin() + std::ptrdiff_t(first));
  }
  void reallocateIndices(std::size_t capacity, const std::uint32_t* data,
                         std::size_t count) override {
    if (count > capacity) note("reallocateIndices", count, capacity);
    indices.assign(capacity, kPoisonIndex);
    std::copy(data, data + std::min(count, capacity), indices.begin());
  }
  void writeIndices(std::size_t first, std::size_t count, const std::uint32_t* data) override {
    if (first + count > indices.size()) return note("writeIndices", first + count, indices.size());
    std::copy(data, data + count, indices.begin() + std::ptrdiff_t(first));
  }

 private:
  void note(const char* what, std::size_t end, std::size_t size) {
    if (outOfBounds.empty())
      outOfBounds =
          std::string(what) + " to " + std::to_string(end) + " of " + std::to_string(size);
  }
};

// A triangle as its corners' float positions and normals, in a canonical rotation.
using Corner = std::array<float, 6>;
using Triangle = std::array<Corner, 3>;

Triangle canonical(Triangle t) {
  while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
  return t;
}

Corner cornerOf(const glm::dvec3& p, const glm::dvec3& n) {
  return {float(p.x), float(p.y), float(p.z), float(n.x), float(n.y), float(n.z)};
}

Corner cornerOf(const GpuVertex& v) {
  return {v.position[0], v.position[1], v.position[2], v.normal[0], v.normal[1], v.normal[2]};
}

// "" when the fake GPU draws exactly `mesh`, else what differs first.
std::string compareDrawn(const FakeGpu& gpu, const SurfaceUploader& uploader,
                         const geometry::SurfaceMesh& mesh) {
  if (!gpu.outOfBounds.empty()) return "a write past the storage: " + gpu.outOfBounds;
  if (uploader.indexEnd() > gpu.indices.size()) return "indices drawn past the index buffer";
  std::vector<Triangle> drawn, expected;
  for (std::size_t i = 0; i + 2 < uploader.indexEnd(); i += 3) {
    const std::uint32_t a = gpu.indices[i], b = gpu.indices[i + 1], c = gpu.indices[i + 2];
    if (a == kPoisonIndex || b == kPoisonIndex || c == kPoisonIndex) {
      return "index " + std::to_string(i) + " was drawn but never written";
    }
    if (a == 0 && b == 0 && c == 0) continue;  // padding
    Triangle t;
    const std::uint32_t corners[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      if (corners[k] >= gpu.vertices.size())
        return "triangle " + std::to_string(i / 3) + " refers past the vertices";
      const GpuVertex& v = gpu.vertices[corners[k]];
      if (isPoison(v))
        return "vertex " + std::to_string(corners[k]) + " is drawn but was never written";
      if (std::isnan(v.position[0]))
        return "vertex " + std::to_string(corners[k]) + " is dead but drawn";
      t[std::size_t(k)] = cornerOf(v);
    }
    drawn.push_back(canonical(t));
  }
  for (const glm::u32vec3& tri : mesh.triangles) {
    Triangle t;
    for (int k = 0; k < 3; ++k)
      t[std::size_t(k)] = cornerOf(mesh.positionsMm[tri[k]], mesh.normals[tri[k]]);
    expected.push_back(canonical(t));
  }
  if (drawn.size() != expected.size()) {
    return "drawn " + std::to_string(drawn.size()) + " triangles, the mesh has " +
           std::to_string(expected.size());
  }
  std::sort(drawn.begin(), drawn.end());
  std::sort(expected.begin(), expected.end());
  if (drawn != expected) return "the drawn triangles differ from the mesh's";
  if (uploader.triangleCount() != mesh.triangleCount())
    return "the uploader counts other triangles";
  return "";
}

// Sets every voxel within radiusMm of centreMm to `fill`, with a random partial fill on the
// rim so that vertices also move, not only appear and vanish.
void paintBall(VoxelGrid& grid, glm::dvec3 centreVox, double radiusVox, bool remove,
               std::mt19937& rng) {
  std::uniform_int_distribution<int> steps(1, geometry::kFillSteps - 1);
  const glm::ivec3 dims = grid.dims();
  const int r = int(std::ceil(radiusVox)) + 1;
  for (int z = int(centreVox.z) - r; z <= int(centreVox.z) + r; ++z) {
    for (int y = int(centreVox.y) - r; y <= int(centreVox.y) + r; ++y) {
      for (int x = int(centreVox.x) - r; x <= int(centreVox.x) + r; ++x) {
        if (x < 0 || y < 0 || z < 0 || x >= dims.x || y >= dims.y || z >= dims.z) continue;
        const double d = glm::length(glm::dvec3(x, y, z) + 0.5 - centreVox);
        if (d > radiusVox + 0.5) continue;
        geometry::Fill fill = remove ? 0 : geometry::kFillFull;
        if (d > radiusVox - 0.5)
          fill = geometry::Fill(steps(rng) * geometry::kFillPerStep);  // the rim
        grid.set({x, y, z}, fill, fill > 0 ? 1 : 0);
      }
    }
  }
}

TEST(SurfaceUpload, TheFakeGpuDrawsTheUpdatersMeshAfterEveryRandomDrillingStep) {
  // A ball of bone in a 40-voxel cube: five bricks a side, so edits cross brick boundaries.
  VoxelGrid grid({40, 40, 40}, glm::dvec3(0.0), 0.5);
  std::mt19937 rng(32);
  paintBall(grid, glm::dvec3(20.0), 12.0, false, rng);
  grid.clearDirty();
  geometry::SurfaceUpdater updater(grid);
  FakeGpu gpu;
  SurfaceUploader uploader(gpu);
  uploader.apply(updater.takeChanges());
  ASSERT_EQ(compareDrawn(gpu, uploader, updater.mesh()), "");

  std::uniform_real_distribution<double> where(6.0, 34.0), size(1.0, 4.0), chance(0.0, 1.0);
  std::size_t reallocations = 0, moved = 0, partialWrites = 0;
  for (int step = 0; step < 120; ++step) {
    // Mostly drilling; now and then bone added, so bricks outgrow their regions.
    const bool remove = chance(rng) < 0.8;
    const int balls = 1 + int(chance(rng) * 3);
    for (int b = 0; b < balls; ++b)
      paintBall(grid, {where(rng), where(rng), where(rng)}, size(rng), remove, rng);
    updater.update(grid.dirtyBricks());
    grid.clearDirty();
    const UploadStats& stats = uploader.apply(updater.takeChanges());
    reallocations += stats.vertexReallocations + stats.indexReallocations;
    moved += stats.bricksMoved;
    partialWrites += stats.vertexWrites + stats.indexWrites;
    ASSERT_EQ(compareDrawn(gpu, uploader, updater.mesh()), "") << "step " << step;
    // The GPU holds what the uploader's mirror says, wherever it is drawn from.
    ASSERT_EQ(0, std::memcmp(gpu.indices.data(), uploader.indices().data(),
                             uploader.indexEnd() * sizeof(std::uint32_t)))
        << "step " << step;
  }
  // The run went through every path of the bookkeeping: writes in place, regions moved, and
  // whole-buffer uploads past the first.
  EXPECT_GT(partialWrites, 0u);
  EXPECT_GT(moved, 0u);
  EXPECT_GT(reallocations, 0u);
}

// A new bone: reset(), then a delta with everything, and the GPU draws the new surface only.
TEST(SurfaceUpload, AfterAResetTheFakeGpuDrawsTheNewSurfaceOnly) {
  std::mt19937 rng(7);
  VoxelGrid first({24, 24, 24}, glm::dvec3(0.0), 1.0);
  paintBall(first, glm::dvec3(12.0), 8.0, false, rng);
  VoxelGrid second({24, 24, 24}, glm::dvec3(0.0), 1.0);
  paintBall(second, glm::dvec3(8.0), 4.0, false, rng);
  FakeGpu gpu;
  SurfaceUploader uploader(gpu);
  geometry::SurfaceUpdater big(first);
  uploader.apply(big.takeChanges());
  ASSERT_EQ(compareDrawn(gpu, uploader, big.mesh()), "");
  uploader.reset();
  geometry::SurfaceUpdater small(second);
  uploader.apply(small.takeChanges());
  EXPECT_EQ(compareDrawn(gpu, uploader, small.mesh()), "");
}

}  // namespace
}  // namespace osteon::viewer
