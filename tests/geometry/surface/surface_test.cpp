#include "osteon/geometry/surface/surface.h"

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
// The checks themselves: they must see what they are meant to see.

TEST(SurfaceChecks, ProblemListCatchesBrokenSurfaces) {
  VoxelGrid g = emptyGrid({4, 4, 4});
  setFull(g, {1, 1, 1});
  setFull(g, {2, 1, 1});
  const SurfaceMesh good = extractSurface(g);
  ASSERT_EQ(surfaceProblems(good), "");
  SurfaceMesh holed = good;
  holed.triangles.pop_back();
  EXPECT_NE(surfaceProblems(holed).find("borderEdges"), std::string::npos);
  SurfaceMesh flipped = good;
  std::swap(flipped.triangles[0].y, flipped.triangles[0].z);
  EXPECT_NE(surfaceProblems(flipped).find("misorientedEdges"), std::string::npos);
  SurfaceMesh inverted = good;
  for (glm::u32vec3& t : inverted.triangles) std::swap(t.y, t.z);
  EXPECT_NE(surfaceProblems(inverted).find("signed volume"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// The 256 cases, exhaustively.

TEST(SurfaceCases, All256SingleCubeConfigurationsAreWatertightWithAndWithoutSmoothing) {
  std::vector<std::string> failures;
  int nonEmpty = 0;
  for (const Fill background : {Fill(0), kFillFull}) {
    for (const CornerFills mode :
         {CornerFills::Binary, CornerFills::Random, CornerFills::Extreme}) {
      for (int config = 0; config < 256; ++config) {
        std::mt19937 rng(std::uint32_t(1000 + config));  // fixed seed per case
        const VoxelGrid g = singleCubeGrid(config, background, mode, rng);
        std::ostringstream what;
        what << "config " << config << " background " << background << " fills "
             << (mode == CornerFills::Binary   ? "binary"
                 : mode == CornerFills::Random ? "random"
                                               : "extreme");
        const auto f = watertightFailures(g, what.str());
        failures.insert(failures.end(), f.begin(), f.end());
        if (extractSurface(g, smoothing(0)).triangleCount() > 0) ++nonEmpty;
      }
    }
  }
  // Only the empty cube in an empty grid has no surface (3 fill modes).
  EXPECT_EQ(nonEmpty, 2 * 3 * 256 - 3);
  EXPECT_TRUE(failures.empty()) << failures.size() << " failures:" << joinFirst(failures);
}

// A cube alone in an empty grid: its surface is the boundary of the configuration's inside
// corners, so the component count is the number of groups of inside corners joined through
// cube edges or face diagonals (ambiguous faces keep inside corners joined); corners that
// only share the body diagonal stay apart.
TEST(SurfaceCases, ComponentsFollowEdgeAndFaceDiagonalConnectivityOfInsideCorners) {
  std::vector<std::string> failures;
  for (int config = 1; config < 256; ++config) {
    int parent[8];
    for (int c = 0; c < 8; ++c) parent[c] = c;
    const auto find = [&parent](int c) {
      while (parent[c] != c) c = parent[c];
      return c;
    };
    for (int a = 0; a < 8; ++a)
      for (int b = a + 1; b < 8; ++b) {
        const bool bothInside = ((config >> a) & 1) && ((config >> b) & 1);
        if (bothInside && (a ^ b) != 7) parent[find(a)] = find(b);  // all pairs but body diagonals
      }
    int expected = 0;
    for (int c = 0; c < 8; ++c) {
      if (((config >> c) & 1) && find(c) == c) ++expected;
    }
    std::mt19937 rng(7u);
    const SurfaceMesh s = extractSurface(singleCubeGrid(config, 0, CornerFills::Binary, rng));
    const MeshTopology topo = topologyOf(s);
    if (int(topo.components) != expected || topo.eulerCharacteristic != 2 * expected) {
      failures.push_back("config " + std::to_string(config) + ": components " +
                         std::to_string(topo.components) + " chi " +
                         std::to_string(topo.eulerCharacteristic) + ", expected " +
                         std::to_string(expected) + " spheres");
    }
  }
  EXPECT_TRUE(failures.empty()) << joinFirst(failures);
}

// ---------------------------------------------------------------------------------------------
// Hard volumes: noise, checkerboards, single voxels, thin walls, tunnels.

TEST(SurfaceHardVolumes, RandomNoiseIsWatertightAfterEverySmoothing) {
  std::vector<std::string> failures;
  for (const auto& [n, seeds] : {std::pair<int, int>{12, 3}, {16, 2}, {20, 1}}) {
    for (std::uint32_t seed = 1; seed <= std::uint32_t(seeds); ++seed) {
      const VoxelGrid g = test::noiseGrid(n, seed);
      const auto f =
          watertightFailures(g, "noise " + std::to_string(n) + "^3 seed " + std::to_string(seed));
      failures.insert(failures.end(), f.begin(), f.end());
    }
  }
  EXPECT_TRUE(failures.empty()) << failures.size() << " failures:" << joinFirst(failures);
}

// Bricks are extracted in parallel; numbering must not depend on the scheduling.
TEST(SurfaceHardVolumes, ExtractionIsDeterministic) {
  std::mt19937 rng(99u);
  const int n = 30;
  VoxelGrid g = emptyGrid({n, n, n});
  std::uniform_int_distribution<int> fill(0, kFillFull);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) g.set({x, y, z}, Fill(fill(rng)), 1);
  const SurfaceMesh a = extractSurface(g);
  for (int run = 0; run < 3; ++run) {
    const SurfaceMesh b = extractSurface(g);
    ASSERT_EQ(a.triangles, b.triangles);
    ASSERT_EQ(a.positionsMm, b.positionsMm);
    ASSERT_EQ(a.normals, b.normals);
    ASSERT_EQ(a.brickRanges.size(), b.brickRanges.size());
  }
}

// Outputs grow slab by slab, with room for as much as the thread's last extraction made: the
// result is the same on one thread or many, after a larger or a smaller extraction, and a
// small mesh does not keep a large one's room.
TEST(SurfaceHardVolumes, ExtractionDependsOnNeitherThreadsNorTheLastExtraction) {
  std::mt19937 rng(7u);
  const auto noise = [&](int n) {
    VoxelGrid g = emptyGrid({n, n, n});
    std::uniform_int_distribution<int> fill(0, kFillFull);
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) g.set({x, y, z}, Fill(fill(rng)), 1);
    return g;
  };
  const VoxelGrid large = noise(40), small = noise(9);
  SurfaceOptions direct;
  direct.smoothIterations = 0;
  for (const SurfaceOptions& options : {SurfaceOptions{}, direct}) {
    const SurfaceMesh smallFirst = extractSurface(small, options);
    const SurfaceMesh largeMany = extractSurface(large, options);
    const SurfaceMesh smallAfter = extractSurface(small, options);
    EXPECT_EQ(smallFirst.triangles, smallAfter.triangles);
    EXPECT_EQ(smallFirst.positionsMm, smallAfter.positionsMm);
    EXPECT_LE(smallAfter.positionsMm.capacity(), 2 * smallAfter.positionsMm.size() + 4096);
    EXPECT_LE(smallAfter.triangles.capacity(), 2 * smallAfter.triangles.size() + 4096);
    tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
    const SurfaceMesh largeOne = extractSurface(large, options);
    EXPECT_EQ(largeMany.triangles, largeOne.triangles);
    EXPECT_EQ(largeMany.positionsMm, largeOne.positionsMm);
    EXPECT_EQ(largeMany.brickRanges.size(), largeOne.brickRanges.size());
  }
}

// Fills only at the extremes next to the iso level and at 0/full: vertices pile into the
// clamp margins at both ends of their edges, the hardest case for smoothing.
TEST(SurfaceHardVolumes, ExtremeNoiseIsWatertightAfterEverySmoothing) {
  std::vector<std::string> failures;
  for (const std::uint32_t seed : {11u, 12u}) {
    const VoxelGrid g = test::extremeNoiseGrid(14, seed);
    const auto f = watertightFailures(g, "extreme noise seed " + std::to_string(seed));
    failures.insert(failures.end(), f.begin(), f.end());
  }
  EXPECT_TRUE(failures.empty()) << failures.size() << " failures:" << joinFirst(failures);
}

TEST(SurfaceHardVolumes, CheckerboardIsWatertightWithACavityPerInteriorEmptyVoxel) {
  for (const int parity : {0, 1}) {
    const int n = 10;
    VoxelGrid g = emptyGrid({n, n, n});
    int interiorEmpty = 0;
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          if ((x + y + z) % 2 == parity) {
            setFull(g, {x, y, z});
          } else if (x > 0 && y > 0 && z > 0 && x < n - 1 && y < n - 1 && z < n - 1) {
            ++interiorEmpty;
          }
        }
    SCOPED_TRACE("parity " + std::to_string(parity));
    EXPECT_EQ(joinFirst(watertightFailures(g, "checkerboard")), "");
    // Ambiguous faces join the full voxels into one solid; each empty voxel not on the grid's
    // border is sealed in as its own cavity (an octahedron).
    const MeshTopology topo = topologyOf(extractSurface(g));
    EXPECT_EQ(topo.components, std::size_t(1 + interiorEmpty));
    EXPECT_EQ(topo.eulerCharacteristic, 2LL * (1 + interiorEmpty));
  }
}

TEST(SurfaceHardVolumes, SingleVoxelIsAnOctahedronAnywhereInTheGrid) {
  // In the middle, and at a grid corner (its cells are in the border layer outside the grid).
  for (const glm::ivec3 v : {glm::ivec3(1, 1, 1), glm::ivec3(0, 0, 0), glm::ivec3(2, 0, 2)}) {
    SCOPED_TRACE("voxel " + std::to_string(v.x) + "," + std::to_string(v.y) + "," +
                 std::to_string(v.z));
    for (const Fill f : {kFillHalf, Fill(12345), kFillFull}) {
      VoxelGrid g = emptyGrid({3, 3, 3}, 0.5);
      g.set(v, f, 1);
      EXPECT_EQ(joinFirst(watertightFailures(g, "fill " + std::to_string(f))), "");
      const SurfaceMesh s = extractSurface(g, smoothing(0));
      EXPECT_EQ(s.triangleCount(), 8u);
      EXPECT_EQ(s.vertexCount(), 6u);
      EXPECT_EQ(topologyOf(s).eulerCharacteristic, 2);
      // Each vertex sits on an axis through the voxel centre, at the interpolated distance.
      const double t = (double(kFillHalf) - 0.5) / double(f);  // from the empty neighbour's centre
      const double expectedOffset = std::max(1.0 - std::clamp(t, 1e-3, 1.0 - 1e-3), 0.0) * 0.5;
      const glm::dvec3 centre = g.voxelCentreMm(v);
      for (const glm::dvec3& p : s.positionsMm) {
        EXPECT_NEAR(glm::length(p - centre), expectedOffset, 1e-12);
      }
    }
  }
}

TEST(SurfaceHardVolumes, OneVoxelThinWallsAreWatertight) {
  const int n = 12;
  // Axis-aligned wall, with and without a one-voxel hole.
  for (const bool holed : {false, true}) {
    VoxelGrid g = emptyGrid({n, n, n});
    for (int z = 2; z < 10; ++z)
      for (int y = 2; y < 10; ++y) {
        if (!(holed && y == 5 && z == 6)) setFull(g, {5, y, z});
      }
    SCOPED_TRACE(holed ? "holed wall" : "wall");
    EXPECT_EQ(joinFirst(watertightFailures(g, "wall")), "");
    const MeshTopology topo = topologyOf(extractSurface(g));
    EXPECT_EQ(topo.components, 1u);
    EXPECT_EQ(topo.eulerCharacteristic, holed ? 0 : 2);
  }
  // Diagonal wall: voxels (i, i, z) touch only along edges, so every cell across the wall
  // has an ambiguous face; the face rule joins them into one slab.
  {
    VoxelGrid g = emptyGrid({n, n, n});
    for (int z = 2; z < 10; ++z)
      for (int i = 1; i < 11; ++i) setFull(g, {i, i, z});
    SCOPED_TRACE("diagonal wall");
    EXPECT_EQ(joinFirst(watertightFailures(g, "diagonal wall")), "");
    const MeshTopology topo = topologyOf(extractSurface(g));
    EXPECT_EQ(topo.components, 1u);
    EXPECT_EQ(topo.eulerCharacteristic, 2);
  }
  // Body-diagonal chain: voxels (i, i, i) touch only at corners, which are not joined.
  {
    VoxelGrid g = emptyGrid({n, n, n});
    for (int i = 1; i < 11; ++i) setFull(g, {i, i, i});
    SCOPED_TRACE("corner chain");
    EXPECT_EQ(joinFirst(watertightFailures(g, "corner chain")), "");
    const MeshTopology topo = topologyOf(extractSurface(g));
    EXPECT_EQ(topo.components, 10u);
    EXPECT_EQ(topo.eulerCharacteristic, 20);
  }
}

TEST(SurfaceHardVolumes, OneVoxelTunnelsAreWatertightAndOpen) {
  const int n = 12;
  // A block with a one-voxel straight tunnel along z, and one with a tunnel that turns (an L
  // through two faces).
  for (const bool bent : {false, true}) {
    VoxelGrid g = emptyGrid({n, n, n});
    for (int z = 2; z < 10; ++z)
      for (int y = 2; y < 10; ++y)
        for (int x = 2; x < 10; ++x) setFull(g, {x, y, z});
    if (!bent) {
      for (int z = 2; z < 10; ++z) g.set({5, 5, z}, 0, 0);
    } else {
      for (int z = 2; z <= 6; ++z) g.set({5, 5, z}, 0, 0);
      for (int x = 5; x < 10; ++x) g.set({x, 5, 6}, 0, 0);
    }
    SCOPED_TRACE(bent ? "bent tunnel" : "straight tunnel");
    EXPECT_EQ(joinFirst(watertightFailures(g, "tunnel")), "");
    const MeshTopology topo = topologyOf(extractSurface(g));
    EXPECT_EQ(topo.components, 1u);
    EXPECT_EQ(topo.eulerCharacteristic, 0);  // genus 1: the tunnel stays open
  }
}

TEST(SurfaceHardVolumes, EmptyAndFullGrids) {
  const VoxelGrid empty = emptyGrid({9, 9, 9});
  const SurfaceMesh none = extractSurface(empty);
  EXPECT_EQ(none.triangleCount(), 0u);
  EXPECT_EQ(none.vertexCount(), 0u);
  EXPECT_TRUE(none.brickRanges.empty());

  // A full grid closes at the grid border (outside reads as empty): one box.
  VoxelGrid full = emptyGrid({9, 9, 9});
  for (std::size_t b = 0; b < full.brickCount(); ++b) full.setBrickUniform(b, kFillFull, 1);
  EXPECT_EQ(joinFirst(watertightFailures(full, "full grid")), "");
  const SurfaceMesh box = extractSurface(full, smoothing(0));
  EXPECT_EQ(topologyOf(box).eulerCharacteristic, 2);
  // Faces at a = 1/2 (+ the iso level's 1/2 unit below half full) outside the outer voxel
  // centres, the 12 edges bevelled (a^2 / 2 per unit length) and the 8 corners cut (5 a^3 / 6).
  const double a = 1.0 - (double(kFillHalf) - 0.5) / double(kFillFull);
  const double span = 8.0;  // between the outer voxel centres
  const double expected =
      std::pow(span + 2.0 * a, 3) - 12.0 * span * a * a / 2.0 - 8.0 * 5.0 * a * a * a / 6.0;
  EXPECT_NEAR(signedVolumeMm3(box.toTriangleMesh()) / expected, 1.0, 1e-12);
}

}  // namespace
}  // namespace osteon::geometry
