// Shading normals from the fill's gradient (viewer/src/field_normals.h): on a voxelized sphere
// at the seed's two voxel sizes they follow the true sphere far better than the extracted
// mesh's normals (the terraces), and uploading them leaves every position as extracted.
#include "field_normals.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "osteon/geometry/surface/surface_updater.h"
#include "surface_upload.h"

namespace osteon::viewer {
namespace {

using geometry::VoxelGrid;

// A sphere's partial volume per voxel (8^3 samples), as a voxelizer gives it.
VoxelGrid sphereGrid(double radiusMm, double voxelMm, const glm::dvec3& centre) {
  const int n = int(std::ceil(2.0 * radiusMm / voxelMm)) + 6;
  VoxelGrid grid({n, n, n}, centre - 0.5 * double(n) * voxelMm, voxelMm);
  constexpr int kSub = 8;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        int inside = 0;
        for (int s = 0; s < kSub * kSub * kSub; ++s) {
          const glm::dvec3 sub(double(s % kSub) + 0.5, double((s / kSub) % kSub) + 0.5,
                               double(s / (kSub * kSub)) + 0.5);
          const glm::dvec3 p = grid.worldFromGrid(glm::dvec3(x, y, z) + sub / double(kSub));
          if (glm::length(p - centre) < radiusMm) ++inside;
        }
        if (inside == 0) continue;
        const int steps = int(std::lround(255.0 * inside / double(kSub * kSub * kSub)));
        grid.set({x, y, z}, geometry::Fill(steps * geometry::kFillPerStep), 20);
      }
  grid.clearDirty();
  return grid;
}

class CaptureGpu : public SurfaceUploadTarget {
 public:
  std::vector<GpuVertex> vertices;
  void reallocateVertices(std::size_t capacity, const GpuVertex* data, std::size_t count) override {
    vertices.assign(data, data + count);
    vertices.resize(capacity);
  }
  void writeVertices(std::size_t first, std::size_t count, const GpuVertex* data) override {
    std::copy(data, data + count, vertices.begin() + std::ptrdiff_t(first));
  }
  void reallocateIndices(std::size_t, const std::uint32_t*, std::size_t) override {}
  void writeIndices(std::size_t, std::size_t, const std::uint32_t*) override {}
};

double errorDeg(const glm::dvec3& n, const glm::dvec3& truth) {
  const double c = glm::dot(glm::normalize(n), glm::normalize(truth));
  return glm::degrees(std::acos(std::clamp(c, -1.0, 1.0)));
}

TEST(FieldNormalsTest, TheFillGradientFollowsTheSphereWithoutTerraces) {
  for (const double voxelMm : {1.2, 0.54}) {
    SCOPED_TRACE(voxelMm);
    const glm::dvec3 centre(3.1, -2.3, 7.7);
    const VoxelGrid grid = sphereGrid(20.0, voxelMm, centre);
    geometry::SurfaceUpdater updater(grid);
    const geometry::SurfaceMesh mesh = updater.mesh();
    ASSERT_GT(mesh.vertexCount(), 1000u);
    CaptureGpu gpu;
    SurfaceUploader uploader(gpu);
    uploader.setNormalField(&grid);
    uploader.apply(updater.takeChanges());
    double meshSum = 0.0, fieldSum = 0.0, fieldWorst = 0.0;
    std::size_t n = 0, moved = 0;
    for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
      const glm::dvec3& p = mesh.positionsMm[i];
      const glm::dvec3 truth = p - centre;
      const glm::dvec3 field = fieldNormal(grid, p, mesh.normals[i]);
      meshSum += errorDeg(mesh.normals[i], truth);
      fieldSum += errorDeg(field, truth);
      fieldWorst = std::max(fieldWorst, errorDeg(field, truth));
      ++n;
      // What the uploader wrote: the same position, the field's normal.
      const GpuVertex& v = gpu.vertices[i];
      if (v.position[0] != float(p.x) || v.position[1] != float(p.y) || v.position[2] != float(p.z))
        ++moved;
      EXPECT_NEAR(v.normal[0], float(field.x), 1e-6f);
    }
    EXPECT_EQ(moved, 0u);
    const double meshMean = meshSum / double(n), fieldMean = fieldSum / double(n);
    EXPECT_LT(fieldMean, 2.0);  // within two degrees of the sphere on average
    EXPECT_LT(fieldMean, 0.5 * meshMean) << "mesh " << meshMean;  // at most half the mesh's
    EXPECT_LT(fieldWorst, 6.0);
  }
}

TEST(FieldNormalsTest, WhereTheGradientVanishesTheMeshNormalIsKept) {
  VoxelGrid grid({8, 8, 8}, glm::dvec3(0.0), 1.0);
  const glm::dvec3 n(0.0, 0.0, 1.0);
  EXPECT_EQ(fieldNormal(grid, {4.0, 4.0, 4.0}, n), n);  // empty everywhere: no gradient
}

}  // namespace
}  // namespace osteon::viewer
