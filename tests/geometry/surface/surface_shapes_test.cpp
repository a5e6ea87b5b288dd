// Surfaces of real shapes: topology, the naive per-cube baseline, a sphere (volume, normals,
// brick ranges), and the options' checks.
#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/shapes.h"
#include "support/surface_grids.h"
#include "surface_checks.h"

namespace osteon::geometry {
namespace {

using namespace osteon::test;
using namespace surface_test;

constexpr double kPi = 3.14159265358979323846;
// ---------------------------------------------------------------------------------------------
// Topology of real shapes.

TEST(SurfaceTopology, EulerCharacteristicOfSphereTorusAndTwoHolePlate) {
  const VoxelGrid sphere = voxelizeAt(test::makeSphere(10.0, 128, 64), 1.0);
  const MeshTopology s = topologyOf(extractSurface(sphere));
  EXPECT_TRUE(s.closed() && s.manifold() && s.consistentlyOriented());
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.eulerCharacteristic, 2);

  const VoxelGrid torus = voxelizeAt(test::makeTorus(10.0, 4.0, 128, 64), 0.8);
  const MeshTopology t = topologyOf(extractSurface(torus));
  EXPECT_TRUE(t.closed() && t.manifold() && t.consistentlyOriented());
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.eulerCharacteristic, 0);

  // A plate 12 x 8 x 3 voxels with two 2 x 2 through-holes: genus 2.
  VoxelGrid plate = emptyGrid({16, 12, 7});
  for (int z = 2; z < 5; ++z)
    for (int y = 2; y < 10; ++y)
      for (int x = 2; x < 14; ++x) {
        const bool hole = y >= 5 && y < 7 && ((x >= 4 && x < 6) || (x >= 10 && x < 12));
        if (!hole) setFull(plate, {x, y, z});
      }
  EXPECT_EQ(joinFirst(watertightFailures(plate, "two-hole plate")), "");
  const MeshTopology p = topologyOf(extractSurface(plate));
  EXPECT_EQ(p.components, 1u);
  EXPECT_EQ(p.eulerCharacteristic, -2);
}

// ---------------------------------------------------------------------------------------------
// The naive baseline.

class SurfaceNaive : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    grid_ = new VoxelGrid(voxelizeAt(test::makeSphere(10.0, 128, 64), 1.0));
  }
  static void TearDownTestSuite() {
    delete grid_;
    grid_ = nullptr;
  }
  static SurfaceMesh extract(SurfaceMethod method, int passes) {
    SurfaceOptions o = smoothing(passes);
    o.method = method;
    return extractSurface(*grid_, o);
  }
  static VoxelGrid* grid_;
};
VoxelGrid* SurfaceNaive::grid_ = nullptr;

TEST_F(SurfaceNaive, PerCubeVerticesLeaveBorderEdgesWhereCrackFreeHasNone) {
  for (const int passes : {0, 2}) {
    SCOPED_TRACE(std::to_string(passes) + " passes");
    const MeshTopology naive = topologyOf(extract(SurfaceMethod::Naive, passes));
    const MeshTopology crackFree = topologyOf(extract(SurfaceMethod::CrackFree, passes));
    EXPECT_GT(naive.borderEdges, 1000u);
    EXPECT_EQ(crackFree.borderEdges, 0u);
    EXPECT_TRUE(crackFree.closed() && crackFree.manifold());
  }
}

TEST_F(SurfaceNaive, UnsmoothedNaiveIsTheSameGeometryWithoutSharing) {
  const SurfaceMesh naive = extract(SurfaceMethod::Naive, 0);
  const SurfaceMesh crackFree = extract(SurfaceMethod::CrackFree, 0);
  ASSERT_EQ(naive.triangleCount(), crackFree.triangleCount());
  EXPECT_GT(naive.vertexCount(), 2 * crackFree.vertexCount());  // each vertex in several cubes
  // Same cells, same loops, same order: triangle for triangle the same corners.
  std::size_t differing = 0;
  for (std::size_t i = 0; i < naive.triangleCount(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const glm::dvec3 d = naive.positionsMm[naive.triangles[i][c]] -
                           crackFree.positionsMm[crackFree.triangles[i][c]];
      if (glm::length(d) > 1e-12) ++differing;
    }
  }
  EXPECT_EQ(differing, 0u);
  const double areaNaive = surfaceAreaMm2(naive.toTriangleMesh());
  const double areaCrackFree = surfaceAreaMm2(crackFree.toTriangleMesh());
  EXPECT_NEAR(areaNaive / areaCrackFree, 1.0, 1e-9);
  EXPECT_NEAR(signedVolumeMm3(naive.toTriangleMesh()) / signedVolumeMm3(crackFree.toTriangleMesh()),
              1.0, 1e-9);
}

// Smoothing the naive surface moves each cube's copy of an edge vertex differently: copies
// that coincided drift apart, which is the crack.
TEST_F(SurfaceNaive, SmoothingSplitsTheCopiesOfAnEdgeVertex) {
  const auto distinct = [](const SurfaceMesh& s) {
    std::set<std::tuple<double, double, double>> seen;
    for (const glm::dvec3& p : s.positionsMm) seen.emplace(p.x, p.y, p.z);
    return seen.size();
  };
  const std::size_t before = distinct(extract(SurfaceMethod::Naive, 0));
  const std::size_t after = distinct(extract(SurfaceMethod::Naive, 2));
  // Unsmoothed, the copies coincide: as many places as the crack-free mesh has vertices.
  EXPECT_EQ(before, extract(SurfaceMethod::CrackFree, 0).vertexCount());
  EXPECT_GT(after, before + before / 2);
}

// ---------------------------------------------------------------------------------------------
// Accuracy and normals on a sphere.

class SurfaceSphere : public ::testing::Test {
 protected:
  static constexpr double kRadius = 10.0;
  static constexpr double kVoxel = 0.5;
  static void SetUpTestSuite() {
    grid_ = new VoxelGrid(voxelizeAt(test::makeSphere(kRadius, 512, 256), kVoxel));
    surface_ = new SurfaceMesh(extractSurface(*grid_));  // default: 2 passes, normals
  }
  static void TearDownTestSuite() {
    delete surface_;
    delete grid_;
    surface_ = nullptr;
    grid_ = nullptr;
  }
  static VoxelGrid* grid_;
  static SurfaceMesh* surface_;
};
VoxelGrid* SurfaceSphere::grid_ = nullptr;
SurfaceMesh* SurfaceSphere::surface_ = nullptr;

TEST_F(SurfaceSphere, EnclosedVolumeMatchesTheGridAndTheSphere) {
  const double volume = signedVolumeMm3(surface_->toTriangleMesh());
  const double exact = 4.0 / 3.0 * kPi * kRadius * kRadius * kRadius;
  EXPECT_NEAR(volume / grid_->filledVolumeMm3(), 1.0, 0.01);
  EXPECT_NEAR(volume / exact, 1.0, 0.015);
  EXPECT_EQ(surfaceProblems(*surface_), "");
}

TEST_F(SurfaceSphere, EveryVertexLiesWithinOneVoxelOfTheSphere) {
  double worst = 0.0;
  for (const glm::dvec3& p : surface_->positionsMm)
    worst = std::max(worst, std::abs(glm::length(p) - kRadius));
  EXPECT_LT(worst, kVoxel);
}

TEST_F(SurfaceSphere, NormalsAreUnitAndPointOutward) {
  ASSERT_EQ(surface_->normals.size(), surface_->vertexCount());
  double worstLength = 0.0;
  double worstDot = 1.0;
  for (std::size_t i = 0; i < surface_->vertexCount(); ++i) {
    const glm::dvec3& n = surface_->normals[i];
    worstLength = std::max(worstLength, std::abs(glm::length(n) - 1.0));
    worstDot = std::min(worstDot, glm::dot(n, glm::normalize(surface_->positionsMm[i])));
  }
  EXPECT_LT(worstLength, 1e-12);
  EXPECT_GT(worstDot, 0.9);
}

TEST_F(SurfaceSphere, NormalsAreLeftOutWhenNotAsked) {
  SurfaceOptions o;
  o.computeNormals = false;
  const SurfaceMesh s = extractSurface(*grid_, o);
  EXPECT_TRUE(s.normals.empty());
  EXPECT_EQ(s.triangles, surface_->triangles);
  EXPECT_EQ(s.positionsMm, surface_->positionsMm);
}

// ---------------------------------------------------------------------------------------------
// Brick ranges.

TEST_F(SurfaceSphere, BrickRangesCoverEveryTriangleExactlyOnce) {
  const auto& ranges = surface_->brickRanges;
  ASSERT_GT(ranges.size(), 8u);
  std::vector<int> covered(surface_->triangleCount(), 0);
  std::uint64_t total = 0;
  std::set<std::int64_t> bricks;
  for (const auto& r : ranges) {
    EXPECT_GT(r.count, 0u);
    ASSERT_LE(std::uint64_t(r.first) + r.count, surface_->triangleCount());
    for (std::uint32_t i = r.first; i < r.first + r.count; ++i) ++covered[i];
    total += r.count;
    if (r.brick >= 0) {
      EXPECT_TRUE(bricks.insert(r.brick).second) << "brick " << r.brick << " twice";
    }
  }
  EXPECT_EQ(total, surface_->triangleCount());
  EXPECT_EQ(std::count(covered.begin(), covered.end(), 1), std::ptrdiff_t(covered.size()));
}

// Every range holds the triangles of the cells of one brick: cells (x, y, z) with x in
// [8 bx, 8 bx + 7] (and likewise y, z), or the border layer's cells at -1, so its vertices lie
// in that brick's cell box, one voxel wider than its cells. Cell coordinates here are grid
// coordinates minus 1/2 (voxel centres at integers).
glm::ivec3 cellBrickOfRange(const VoxelGrid& g, const SurfaceMesh& s,
                            const SurfaceMesh::BrickRange& r, bool& inOneBrick) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (std::uint32_t i = r.first; i < r.first + r.count; ++i) {
    for (int c = 0; c < 3; ++c) {
      const glm::dvec3 cell = g.gridFromWorld(s.positionsMm[s.triangles[i][c]]) - 0.5;
      lo = glm::min(lo, cell);
      hi = glm::max(hi, cell);
    }
  }
  const int kB = VoxelGrid::kBrickSize;
  glm::ivec3 cb;
  inOneBrick = true;
  for (int a = 0; a < 3; ++a) {
    cb[a] = int(std::floor(0.5 * (lo[a] + hi[a]) / kB));
    const double first = cb[a] < 0 ? -1.0 : double(cb[a] * kB);
    const double last = cb[a] < 0 ? 0.0 : double(cb[a] * kB + kB);
    if (lo[a] < first - 1e-9 || hi[a] > last + 1e-9) inOneBrick = false;
  }
  return cb;
}

TEST_F(SurfaceSphere, EachBrickRangeHoldsTheCellsOfOneBrick) {
  std::set<std::tuple<int, int, int>> seen;
  for (const auto& r : surface_->brickRanges) {
    bool inOne = false;
    const glm::ivec3 cb = cellBrickOfRange(*grid_, *surface_, r, inOne);
    EXPECT_TRUE(inOne) << "range of brick id " << r.brick;
    EXPECT_TRUE(seen.emplace(cb.x, cb.y, cb.z).second) << "two ranges for one brick";
  }
}

// Each range names its cell brick and the documented key of it.
TEST_F(SurfaceSphere, BrickIdsAreTheDocumentedCellBrickKeys) {
  const VoxelGrid& g = *grid_;
  const glm::ivec3 nb = g.brickDims();
  std::vector<std::string> failures;
  for (const auto& r : surface_->brickRanges) {
    bool inOne = false;
    const glm::ivec3 cb = cellBrickOfRange(g, *surface_, r, inOne);
    const std::int64_t documented =
        (cb.x + 1) + std::int64_t(nb.x + 1) * ((cb.y + 1) + std::int64_t(nb.y + 1) * (cb.z + 1));
    EXPECT_EQ(r.cellBrick, cb);
    if (r.brick != documented) {
      const std::int64_t cellTable =
          (cb.x + 1) + (nb.x + 1) * ((cb.y + 1) + std::int64_t(nb.y + 1) * (cb.z + 1));
      failures.push_back("cells of brick (" + std::to_string(cb.x) + "," + std::to_string(cb.y) +
                         "," + std::to_string(cb.z) + "): id " + std::to_string(r.brick) +
                         ", documented " + std::to_string(documented) +
                         ", cell-brick table index " + std::to_string(cellTable));
    }
  }
  EXPECT_TRUE(failures.empty()) << failures.size() << " of " << surface_->brickRanges.size()
                                << " ranges (grid brickDims " << nb.x << "x" << nb.y << "x" << nb.z
                                << "):" << joinFirst(failures, 5);
}

// ---------------------------------------------------------------------------------------------
// Options.

TEST(SurfaceOptionsCheck, BadOptionsThrowInputError) {
  VoxelGrid g = emptyGrid({3, 3, 3});
  setFull(g, {1, 1, 1});
  const auto with = [](auto change) {
    SurfaceOptions o;
    change(o);
    return o;
  };
  EXPECT_THROW(extractSurface(g, with([](SurfaceOptions& o) { o.smoothIterations = -1; })),
               InputError);
  EXPECT_THROW(extractSurface(g, with([](SurfaceOptions& o) { o.lambda = 0.0; })), InputError);
  EXPECT_THROW(extractSurface(g, with([](SurfaceOptions& o) { o.lambda = 1.5; })), InputError);
  EXPECT_THROW(extractSurface(g, with([](SurfaceOptions& o) { o.lambda = std::nan(""); })),
               InputError);
  EXPECT_THROW(extractSurface(g, with([](SurfaceOptions& o) { o.mu = 0.1; })), InputError);
  // The limits themselves are fine.
  EXPECT_NO_THROW(extractSurface(g, with([](SurfaceOptions& o) { o.smoothIterations = 0; })));
  EXPECT_NO_THROW(extractSurface(g, with([](SurfaceOptions& o) { o.lambda = 1.0; })));
}

TEST(SurfaceOptionsCheck, TimingsAreReported) {
  VoxelGrid g = emptyGrid({6, 6, 6});
  setFull(g, {2, 2, 2});
  setFull(g, {3, 2, 2});
  SurfaceTimings t;
  t.totalMs = -1.0;
  extractSurface(g, {}, &t);
  EXPECT_GE(t.extractMs, 0.0);
  EXPECT_GE(t.smoothMs, 0.0);
  EXPECT_GE(t.normalsMs, 0.0);
  EXPECT_GE(t.totalMs, t.extractMs);
}

}  // namespace
}  // namespace osteon::geometry
