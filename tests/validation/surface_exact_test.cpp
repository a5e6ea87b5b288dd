// Exact checks (CGAL, exact predicates) of the surfaces geometry extracts: no two triangles
// cross, on the grids that stress extraction most, every smoothing variant, and the
// multi-resolution surface of refined and drilled voxels. Geometry's own tests check the
// topology of the same surfaces without CGAL.
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "osteon/geometry/hierarchy/fine_fill.h"
#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/validation/mesh_checks.h"
#include "support/carve.h"
#include "support/shapes.h"
#include "support/surface_grids.h"

namespace osteon::validation {
namespace {

using namespace osteon::geometry;
using namespace osteon::test;

VoxelGrid voxelizeAt(const TriangleMesh& mesh, double voxelSizeMm) {
  VoxelizeOptions options;
  options.voxelSizeMm = voxelSizeMm;
  return voxelize(mesh, options);
}

// Self-intersecting pairs of every smoothing variant's surface, one line per failure.
std::vector<std::string> crossings(const VoxelGrid& grid, const std::string& what) {
  std::vector<std::string> failures;
  for (const auto& [name, options] : smoothingVariants()) {
    const std::size_t pairs =
        selfIntersectingPairs(extractSurface(grid, options).toTriangleMesh(), 10);
    if (pairs)
      failures.push_back(what + ", " + name + ": " + std::to_string(pairs) + " crossing pairs");
  }
  return failures;
}

TriangleMesh tetrahedron(glm::dvec3 o, double size) {
  return {{o, o + glm::dvec3(size, 0, 0), o + glm::dvec3(0, size, 0), o + glm::dvec3(0, 0, size)},
          {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
}

TriangleMesh merged(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  const auto offset = std::uint32_t(a.vertexCount());
  m.positionsMm.insert(m.positionsMm.end(), b.positionsMm.begin(), b.positionsMm.end());
  for (const glm::u32vec3& t : b.triangles) m.triangles.push_back(t + offset);
  return m;
}

TEST(SurfaceChecks, CgalFindsCrossingsInPolygonMeshes) {
  const TriangleMesh one = tetrahedron(glm::dvec3(0.0), 1.0);
  EXPECT_EQ(selfIntersectingPairs(one), 0u);
  EXPECT_FALSE(doesSelfIntersect(one));
  // Two closed tetrahedra overlapping: a polygon mesh of two components.
  const TriangleMesh crossing = merged(one, tetrahedron(glm::dvec3(0.3), 1.0));
  EXPECT_GT(selfIntersectingPairs(crossing), 0u);
  EXPECT_EQ(selfIntersectingPairs(crossing, 1), 1u);
  EXPECT_TRUE(doesSelfIntersect(crossing));
  // Disjoint: none.
  EXPECT_FALSE(doesSelfIntersect(merged(one, tetrahedron(glm::dvec3(2.0), 1.0))));
  // A face folded onto its neighbour across their shared edge.
  const TriangleMesh fold{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0.3, 0}}, {{0, 1, 2}, {1, 0, 3}}};
  EXPECT_EQ(selfIntersectingPairs(fold), 1u);
}

// Soups that are no polygon mesh (pinched vertex, edge used twice the same way) take the
// pairwise fallback, which must neither miss crossings nor count shared vertices and edges.
TEST(SurfaceChecks, CgalFallbackHandlesSoupsThatAreNoPolygonMesh) {
  TriangleMesh pinched = tetrahedron(glm::dvec3(0.0), 1.0);
  pinched.positionsMm.insert(pinched.positionsMm.end(), {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}});
  pinched.triangles.insert(pinched.triangles.end(), {{0, 4, 5}, {0, 6, 4}, {0, 5, 6}, {4, 6, 5}});
  ASSERT_EQ(analyzeTopology(pinched).nonManifoldVertices, 1u);
  EXPECT_EQ(selfIntersectingPairs(pinched), 0u);  // they touch at vertex 0 only
  EXPECT_FALSE(doesSelfIntersect(pinched));

  TriangleMesh piercing = tetrahedron(glm::dvec3(0.0), 1.0);  // shares vertex 0, crosses face 123
  piercing.positionsMm.insert(piercing.positionsMm.end(),
                              {{2, 0.1, 0.1}, {0.1, 2, 0.1}, {0.1, 0.1, 2}});
  piercing.triangles.insert(piercing.triangles.end(), {{0, 5, 4}, {0, 4, 6}, {0, 6, 5}, {4, 5, 6}});
  EXPECT_GT(selfIntersectingPairs(piercing), 0u);
  EXPECT_TRUE(doesSelfIntersect(piercing));

  // Edge 0 -> 1 used twice in the same direction; overlapping, then not.
  const TriangleMesh folded{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0.3, 0}},
                            {{0, 1, 2}, {0, 1, 3}}};
  EXPECT_EQ(selfIntersectingPairs(folded), 1u);
  const TriangleMesh flat{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, -0.3, 0}},
                          {{0, 1, 2}, {0, 1, 3}}};
  EXPECT_EQ(selfIntersectingPairs(flat), 0u);
  // Sharing vertex 0 at an angle without crossing.
  const TriangleMesh fan{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0.2, 0.3}},
                         {{0, 1, 2}, {0, 3, 4}, {0, 1, 3}, {0, 1, 4}}};
  EXPECT_EQ(selfIntersectingPairs(fan), 0u);
}

TEST(SurfaceChecks, CgalSeesAVertexPushedThroughTheSurface) {
  VoxelGrid g = emptyGrid({4, 4, 4});
  setFull(g, {1, 1, 1});
  setFull(g, {2, 1, 1});
  TriangleMesh dented = extractSurface(g).toTriangleMesh();
  EXPECT_EQ(selfIntersectingPairs(dented), 0u);
  const glm::dvec3 c = g.voxelCentreMm({1, 1, 1});
  dented.positionsMm[0] = c + 3.0 * (c - dented.positionsMm[0]);
  EXPECT_GT(selfIntersectingPairs(dented), 0u);
}

TEST(SurfaceExact, All256SingleCubeConfigurationsNeverCross) {
  std::vector<std::string> failures;
  for (const Fill background : {Fill(0), kFillFull}) {
    for (const CornerFills mode :
         {CornerFills::Binary, CornerFills::Random, CornerFills::Extreme}) {
      for (int config = 0; config < 256; ++config) {
        std::mt19937 rng(std::uint32_t(1000 + config));  // the seeds of geometry's test
        const auto f = crossings(singleCubeGrid(config, background, mode, rng),
                                 "config " + std::to_string(config));
        failures.insert(failures.end(), f.begin(), f.end());
      }
    }
  }
  EXPECT_TRUE(failures.empty()) << failures.size() << " failures, first: " << failures.front();
}

TEST(SurfaceExact, NoiseAndExtremeNoiseNeverCross) {
  std::vector<std::string> failures;
  for (const auto& [n, seeds] : {std::pair<int, int>{12, 3}, {16, 2}, {20, 1}}) {
    for (std::uint32_t seed = 1; seed <= std::uint32_t(seeds); ++seed) {
      const auto f = crossings(noiseGrid(n, seed),
                               "noise " + std::to_string(n) + "^3 seed " + std::to_string(seed));
      failures.insert(failures.end(), f.begin(), f.end());
    }
  }
  for (const std::uint32_t seed : {11u, 12u}) {
    const auto f =
        crossings(extremeNoiseGrid(14, seed), "extreme noise seed " + std::to_string(seed));
    failures.insert(failures.end(), f.begin(), f.end());
  }
  EXPECT_TRUE(failures.empty()) << failures.size() << " failures, first: " << failures.front();
}

// Smoothing moves vertices only along their own grid edges; check that this really never
// folds the surface on a real bone and a curved genus-1 shape.
TEST(SurfaceTopology, SmoothingNeverCreatesSelfIntersectionsOnHumerusAndTorus) {
  const VoxelGrid humerus = voxelizeAt(buildHumerusModel().mesh, 1.2);
  const VoxelGrid torus = voxelizeAt(test::makeTorus(10.0, 4.0, 128, 64), 0.6);
  for (const auto& [name, grid] : {std::pair<std::string, const VoxelGrid*>{"humerus", &humerus},
                                   std::pair<std::string, const VoxelGrid*>{"torus", &torus}}) {
    for (const int passes : {2, 10}) {
      SCOPED_TRACE(name + ", " + std::to_string(passes) + " passes");
      const SurfaceMesh s = extractSurface(*grid, smoothing(passes));
      ASSERT_GT(s.triangleCount(), 1000u);
      EXPECT_EQ(analyzeTopology(s.toTriangleMesh()).borderEdges, 0u);
      EXPECT_FALSE(doesSelfIntersect(s.toTriangleMesh()));
      EXPECT_EQ(analyzeTopology(s.toTriangleMesh()).components, 1u);
    }
  }
}

// Refined (levels -1, -2) and drilled regions joined to level 0: no crossings either.
TEST(SurfaceExact, MultiResolutionSurfacesNeverCross) {
  const HumerusModel model = buildHumerusModel();
  const VoxelGrid original = voxelizeAt(model.mesh, 1.2);
  const EmbreeScene scene(model.mesh);
  const FineFillSource source = FineFillSource::sample(original, model.mesh, scene);
  for (const int depth : {1, 2}) {
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
      VoxelGrid grid = original;
      DynamicProximityHierarchy hierarchy =
          DynamicProximityHierarchy::build(grid, DphBuildOptions{});
      RefinementOptions options;
      options.depth = depth;
      RefinedVoxels refined(grid, hierarchy, &source, options);
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> offset(-6.0, 6.0);
      for (int k = 0; k < 4; ++k) {
        const glm::dvec3 at = model.headCentreMm + model.headRadiusMm * model.headAxis +
                              glm::dvec3(offset(rng), offset(rng), offset(rng));
        refined.refineAround(at, 2.0, 0.0);
        test::carveSphere(refined, at, 1.3, 100);
      }
      ASSERT_GT(refined.refinedCount(), 0u);
      const TriangleMesh mesh = extractSurface(grid, refined).toTriangleMesh();
      EXPECT_EQ(selfIntersectingPairs(mesh, 10), 0u) << "depth " << depth << " seed " << seed;
    }
  }
}

}  // namespace
}  // namespace osteon::validation
