#include "osteon/geometry/hierarchy/dph.h"

#include <algorithm>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "osteon/core/error.h"

namespace osteon::geometry {
namespace {

// Seed Fig. 3: five voxels in a plane, xi = 3, inserted V0..V4.
TEST(Dph, ReproducesTheSeedTwoDimensionalExample) {
  const std::vector<glm::ivec3> v = {{7, 8, 0}, {8, 8, 0}, {9, 8, 0}, {9, 7, 0}, {10, 6, 0}};
  DphBuildOptions options;
  options.method = DphBuildMethod::kInsertion;  // Fig. 3 is the seed's insertion order
  options.shuffle = false;
  const DynamicProximityHierarchy h = DynamicProximityHierarchy::build(v, options);
  ASSERT_EQ(h.levelCount(), 3);
  EXPECT_EQ(h.nodeCount(0), 5u);
  ASSERT_EQ(h.nodeCount(1), 3u);
  EXPECT_EQ(h.nodeCount(2), 1u);
  // Level 1: parents centred at V0, V2, V4, created in that order.
  EXPECT_EQ(h.centre(1, 0), v[0]);
  EXPECT_EQ(h.centre(1, 1), v[2]);
  EXPECT_EQ(h.centre(1, 2), v[4]);
  // V1 joins V0's parent, V3 joins V2's, V4 is alone.
  const auto parentCentreOf = [&](const glm::ivec3& voxel) {
    for (std::uint32_t i = 0; i < h.nodeCount(0); ++i) {
      if (h.centre(0, i) == voxel) return h.centre(1, h.parent(0, i));
    }
    return glm::ivec3(-1);
  };
  EXPECT_EQ(parentCentreOf(v[0]), v[0]);
  EXPECT_EQ(parentCentreOf(v[1]), v[0]);
  EXPECT_EQ(parentCentreOf(v[2]), v[2]);
  EXPECT_EQ(parentCentreOf(v[3]), v[2]);
  EXPECT_EQ(parentCentreOf(v[4]), v[4]);
  // Level 2: one root at V0 holding all three level-1 nodes.
  EXPECT_EQ(h.centre(2, h.root()), v[0]);
  for (std::uint32_t i = 0; i < 3; ++i) EXPECT_EQ(h.parent(1, i), h.root());
  EXPECT_EQ(h.halfWidth(1), 1);
  EXPECT_EQ(h.halfWidth(2), 4);
  EXPECT_EQ(h.validate(), "");
}

std::vector<glm::ivec3> randomVoxels(std::mt19937& rng, int extent, double density) {
  std::vector<glm::ivec3> out;
  std::bernoulli_distribution keep(density);
  for (int z = 0; z < extent; ++z)
    for (int y = 0; y < extent; ++y)
      for (int x = 0; x < extent; ++x)
        if (keep(rng)) out.push_back({x, y, z});
  std::shuffle(out.begin(), out.end(), rng);
  return out;
}

struct Shape {
  glm::dvec3 a, b;
  double radius;
};

std::set<std::array<int, 3>> bruteSphere(const std::vector<glm::ivec3>& voxels,
                                         const DynamicProximityHierarchy& h, const Shape& s) {
  std::set<std::array<int, 3>> out;
  for (const glm::ivec3& v : voxels) {
    if (!h.contains(v)) continue;
    if (glm::length(h.voxelCentreMm(v) - s.a) <= s.radius) out.insert({v.x, v.y, v.z});
  }
  return out;
}

std::set<std::array<int, 3>> bruteCapsule(const std::vector<glm::ivec3>& voxels,
                                          const DynamicProximityHierarchy& h, const Shape& s) {
  std::set<std::array<int, 3>> out;
  for (const glm::ivec3& v : voxels) {
    if (!h.contains(v)) continue;
    // Closest point of the segment by its own formula, independent of the query's.
    const glm::dvec3 ab = s.b - s.a;
    const double len2 = glm::dot(ab, ab);
    const double t =
        len2 > 0.0 ? std::clamp(glm::dot(h.voxelCentreMm(v) - s.a, ab) / len2, 0.0, 1.0) : 0.0;
    if (glm::length(h.voxelCentreMm(v) - (s.a + t * ab)) <= s.radius) {
      out.insert({v.x, v.y, v.z});
    }
  }
  return out;
}

// Every query against a scan of all voxels, on random grids and shapes.
void expectQueriesMatchBruteForce(const std::vector<glm::ivec3>& voxels,
                                  const DynamicProximityHierarchy& h, std::mt19937& rng,
                                  double extentMm, int queries) {
  std::uniform_real_distribution<double> pos(-0.2 * extentMm, 1.2 * extentMm);
  std::uniform_real_distribution<double> rad(0.0, 0.35 * extentMm);
  DphQueryScratch scratch;
  for (int q = 0; q < queries; ++q) {
    const Shape s{{pos(rng), pos(rng), pos(rng)}, {pos(rng), pos(rng), pos(rng)}, rad(rng)};
    std::set<std::array<int, 3>> got;
    h.forEachVoxelInSphere(s.a, s.radius, scratch, [&](const glm::ivec3& v) {
      EXPECT_TRUE(got.insert({v.x, v.y, v.z}).second) << "reported twice";
    });
    ASSERT_EQ(got, bruteSphere(voxels, h, s)) << "sphere query " << q;
    got.clear();
    h.forEachVoxelInCapsule(s.a, s.b, s.radius, scratch, [&](const glm::ivec3& v) {
      got.insert({v.x, v.y, v.z});
    });
    ASSERT_EQ(got, bruteCapsule(voxels, h, s)) << "capsule query " << q;

    glm::ivec3 nearest;
    double distance = 0.0;
    const bool found = h.nearestVoxel(s.a, scratch, nearest, distance);
    double best = std::numeric_limits<double>::infinity();
    for (const glm::ivec3& v : voxels) {
      if (h.contains(v)) best = std::min(best, glm::length(h.voxelCentreMm(v) - s.a));
    }
    ASSERT_EQ(found, std::isfinite(best));
    if (found) {
      EXPECT_NEAR(distance, best, 1e-9);
      EXPECT_NEAR(glm::length(h.voxelCentreMm(nearest) - s.a), best, 1e-9);
    }
  }
}

TEST(Dph, QueriesEqualABruteForceScan) {
  for (const int xi : {3, 5}) {
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      std::mt19937 rng(unsigned(seed * 7919 + unsigned(xi)));
      const std::vector<glm::ivec3> voxels = randomVoxels(rng, 24, 0.3);
      DphBuildOptions options;
      options.expansionRatio = xi;
      options.seed = seed;
      options.method = seed == 3u ? DphBuildMethod::kInsertion : DphBuildMethod::kLattice;
      const auto h = DynamicProximityHierarchy::build(voxels, options, {-3.0, 1.5, 2.0}, 0.7);
      ASSERT_EQ(h.validate(), "");
      ASSERT_EQ(h.voxelCount(), voxels.size());
      expectQueriesMatchBruteForce(voxels, h, rng, 24 * 0.7, 60);
    }
  }
}

TEST(Dph, RandomRemovalsKeepEveryInvariantAndQueriesExact) {
  std::mt19937 rng(424242);
  std::vector<glm::ivec3> voxels = randomVoxels(rng, 28, 0.5);
  DphBuildOptions options;
  options.seed = 99;
  auto h = DynamicProximityHierarchy::build(voxels, options, glm::dvec3(0.0), 0.5);
  ASSERT_EQ(h.validate(), "");
  std::vector<glm::ivec3> order = voxels;
  std::shuffle(order.begin(), order.end(), rng);
  const std::size_t total = order.size();
  ASSERT_GT(total, 5000u);
  for (std::size_t i = 0; i < total; ++i) {
    ASSERT_TRUE(h.removeVoxel(order[i]));
    EXPECT_FALSE(h.removeVoxel(order[i])) << "removed twice";
    if (i % 500 == 0 || total - i < 5) {
      ASSERT_EQ(h.validate(), "") << "after " << i + 1 << " removals";
      ASSERT_EQ(h.voxelCount(), total - i - 1);
      expectQueriesMatchBruteForce(voxels, h, rng, 14.0, 5);
    }
  }
  EXPECT_EQ(h.root(), DynamicProximityHierarchy::kNone);
  for (int level = 0; level < h.levelCount(); ++level) EXPECT_EQ(h.nodeCount(level), 0u);
  DphQueryScratch scratch;
  int calls = 0;
  h.forEachVoxelInSphere({7, 7, 7}, 100.0, scratch, [&](const glm::ivec3&) { ++calls; });
  EXPECT_EQ(calls, 0);
}

// A query through a cache gives the walk's answer voxel for voxel, in the walk's order, as the
// tool drifts (small moves answered from the cache), jumps (walks again) and voxels go.
void expectCachedQueriesEqualTheWalk(std::size_t sliceNodes) {
  std::mt19937 rng(8080);
  std::vector<glm::ivec3> voxels = randomVoxels(rng, 30, 0.7);
  const double vs = 0.5;
  auto h = DynamicProximityHierarchy::build(voxels, DphBuildOptions{}, {-1.0, 2.0, 0.5}, vs);
  DphQueryScratch scratch;
  const double radiusMm = 2.1;
  DphNearCache sphereCache(vs, DphNearCache::capacityFor(0.0, radiusMm + vs, vs), sliceNodes);
  DphNearCache capsuleCache(vs, DphNearCache::capacityFor(4.0, radiusMm + vs, vs), sliceNodes);
  sphereCache.reserveFor(h);
  capsuleCache.reserveFor(h);
  std::uniform_real_distribution<double> step(-0.06, 0.06);
  std::uniform_int_distribution<std::size_t> pick(0, voxels.size() - 1);
  glm::dvec3 tip(6.0, 9.0, 7.0);
  const glm::dvec3 axis = glm::normalize(glm::dvec3(0.3, -0.2, 1.0));
  for (int q = 0; q < 600; ++q) {
    tip += glm::dvec3(step(rng), step(rng), step(rng));
    if (q % 97 == 96) tip += glm::dvec3(1.5, -0.7, 0.4);           // a jump beyond the skin
    for (int k = 0; k < 3; ++k) h.removeVoxel(voxels[pick(rng)]);  // drilled away (or already gone)
    const glm::dvec3 back = tip + 4.0 * axis;
    std::vector<glm::ivec3> walked, cached;
    h.forEachVoxelInSphere(tip, radiusMm, scratch,
                           [&](const glm::ivec3& v) { walked.push_back(v); });
    h.forEachVoxelInSphere(tip, radiusMm, scratch, &sphereCache,
                           [&](const glm::ivec3& v) { cached.push_back(v); });
    ASSERT_EQ(cached, walked) << "sphere query " << q;
    ASSERT_FALSE(walked.empty()) << "query " << q << " found nothing to compare";
    walked.clear();
    cached.clear();
    h.forEachVoxelInCapsule(tip, back, radiusMm, scratch,
                            [&](const glm::ivec3& v) { walked.push_back(v); });
    h.forEachVoxelInCapsule(tip, back, radiusMm, scratch, &capsuleCache,
                            [&](const glm::ivec3& v) { cached.push_back(v); });
    ASSERT_EQ(cached, walked) << "capsule query " << q;
  }
  // Most queries came from the cache; the jumps walked, and so did the drift beyond the skin
  // unless slices gathered the next answer in time.
  for (const DphNearCache* c : {&sphereCache, &capsuleCache}) {
    EXPECT_EQ(c->walks() + c->reuses(), 600u);
    EXPECT_GE(c->walks(), 6u);
    EXPECT_GT(c->reuses(), 450u);
    EXPECT_EQ(c->overflows(), 0u);
    if (sliceNodes == 0) {
      EXPECT_EQ(c->sliced(), 0u);
      EXPECT_GT(c->walks(), 6u);
    } else if (sliceNodes >= 64) {  // fewer nodes a slice: the skin runs out first, and it walks
      EXPECT_GT(c->sliced(), 0u);
    }
  }
}

TEST(Dph, CachedQueriesEqualTheWalkInTheSameOrder) {
  expectCachedQueriesEqualTheWalk(0);
}

// Next answers gathered a few nodes per query while voxels go between the slices.
TEST(Dph, CachedQueriesWithSlicesEqualTheWalkInTheSameOrder) {
  for (const std::size_t slice : {7u, 64u, 100000u}) expectCachedQueriesEqualTheWalk(slice);
}

// One cache asked in turn for spheres and capsules: a next answer gathered in slices for one
// kind is never continued or used for the other, so every answer is still the walk's.
TEST(Dph, ACacheAskedForSpheresAndCapsulesInTurnStillGivesTheWalksAnswers) {
  std::mt19937 rng(99);
  const std::vector<glm::ivec3> voxels = randomVoxels(rng, 28, 0.7);
  auto h = DynamicProximityHierarchy::build(voxels, DphBuildOptions{}, glm::dvec3(0.0), 0.5);
  DphQueryScratch scratch;
  DphNearCache cache(0.5, DphNearCache::capacityFor(6.0, 2.0 + 0.5, 0.5), 200);
  cache.reserveFor(h);
  std::uniform_real_distribution<double> step(-0.03, 0.03);
  glm::dvec3 tip(7.0, 7.0, 7.0);
  const glm::dvec3 axis(0.0, 0.6, 0.8);
  for (int q = 0; q < 800; ++q) {
    tip += glm::dvec3(step(rng), step(rng), step(rng));
    std::vector<glm::ivec3> walked, cached;
    if ((q / 25) % 2 == 0) {
      h.forEachVoxelInSphere(tip, 2.0, scratch, [&](const glm::ivec3& v) { walked.push_back(v); });
      h.forEachVoxelInSphere(tip, 2.0, scratch, &cache,
                             [&](const glm::ivec3& v) { cached.push_back(v); });
    } else {
      h.forEachVoxelInCapsule(tip, tip + 6.0 * axis, 2.0, scratch,
                              [&](const glm::ivec3& v) { walked.push_back(v); });
      h.forEachVoxelInCapsule(tip, tip + 6.0 * axis, 2.0, scratch, &cache,
                              [&](const glm::ivec3& v) { cached.push_back(v); });
    }
    ASSERT_EQ(cached, walked) << "query " << q;
  }
  EXPECT_GT(cache.sliced(), 0u);  // next answers gathered in slices did take over

  // The case that needs the rule: a short capsule starts a slice, point queries it covers
  // would finish it as a sphere around one end, and the capsule then asks again.
  DphNearCache mixed(1.0, DphNearCache::capacityFor(1.5, 1.0 + 1.0, 0.5), 8);
  mixed.reserveFor(h);
  const glm::dvec3 a0(7.0, 7.0, 7.0), u(0.0, 0.9, 1.2), v(1.0, 0.0, 0.0);  // a capsule 1.5 mm long
  std::vector<glm::ivec3> walked, cached;
  const auto capsule = [&](const glm::dvec3& a, DphNearCache* c) {
    std::vector<glm::ivec3> out;
    h.forEachVoxelInCapsule(a, a + u, 1.0, scratch, c,
                            [&](const glm::ivec3& w) { out.push_back(w); });
    return out;
  };
  capsule(a0, &mixed);            // walks
  capsule(a0 + 0.4 * v, &mixed);  // from the cache; a slice starts for the capsule
  for (int q = 0; q < 300 && mixed.sliced() == 0;
       ++q) {  // covered point queries until a slice takes over
    h.forEachVoxelInSphere(a0 + 0.4 * v, 0.3, scratch, &mixed, [](const glm::ivec3&) {});
  }
  ASSERT_EQ(mixed.sliced(), 1u);
  EXPECT_EQ(capsule(a0 + 0.4 * v, &mixed), capsule(a0 + 0.4 * v, nullptr));
}

// A cache too small for an answer walks at the query's own radius (counted), and a cache kept
// from one hierarchy never answers for another, however alike.
TEST(Dph, CacheOverflowsAndOtherHierarchiesStillGetTheWalksAnswer) {
  std::mt19937 rng(31);
  const std::vector<glm::ivec3> voxels = randomVoxels(rng, 16, 0.8);
  const auto h1 = DynamicProximityHierarchy::build(voxels, DphBuildOptions{});
  auto h2 = DynamicProximityHierarchy::build(voxels, DphBuildOptions{});
  EXPECT_NE(h1.generation(), h2.generation());
  DphQueryScratch scratch;
  const glm::dvec3 c(8.0, 8.0, 8.0);
  std::vector<glm::ivec3> walked, cached;
  h1.forEachVoxelInSphere(c, 3.0, scratch, [&](const glm::ivec3& v) { walked.push_back(v); });
  DphNearCache tiny(1.0, 10);
  h1.forEachVoxelInSphere(c, 3.0, scratch, &tiny,
                          [&](const glm::ivec3& v) { cached.push_back(v); });
  EXPECT_EQ(cached, walked);
  EXPECT_EQ(tiny.overflows(), 1u);

  DphNearCache cache(1.0, DphNearCache::capacityFor(0.0, 4.0, 1.0));
  cached.clear();
  h1.forEachVoxelInSphere(c, 3.0, scratch, &cache,
                          [&](const glm::ivec3& v) { cached.push_back(v); });
  EXPECT_EQ(cached, walked);
  // The same voxels, but h2 loses one: the cache kept from h1 must not answer for it.
  const glm::ivec3 gone = walked.front();
  ASSERT_TRUE(h2.removeVoxel(gone));
  cached.clear();
  h2.forEachVoxelInSphere(c, 3.0, scratch, &cache,
                          [&](const glm::ivec3& v) { cached.push_back(v); });
  EXPECT_EQ(cached.size(), walked.size() - 1);
  EXPECT_EQ(std::count(cached.begin(), cached.end(), gone), 0);
  EXPECT_EQ(cache.walks(), 2u);
  EXPECT_THROW(DphNearCache(-1.0, 8), InputError);
}

TEST(Dph, BuildsFromAGridAndTracksItsOccupiedVoxels) {
  VoxelGrid grid({40, 30, 20}, {1.0, 2.0, 3.0}, 0.5);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> fill(0, 3);
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 40; ++x)
        if (x > 8) grid.set({x, y, z}, Fill(fill(rng) * 5000), 10);  // some stay 0
  grid.setBrickUniform(grid.brickIndex({0, 0, 0}), kFillFull, 10);   // a full uniform brick
  auto h = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
  EXPECT_EQ(h.validateAgainst(grid), "");
  EXPECT_EQ(h.voxelCount(), grid.countVoxels(1));
  // Removing a voxel from both keeps them in step; from one only is caught.
  const glm::ivec3 v(10, 10, 10);
  if (grid.fill(v) == 0) grid.set(v, kFillFull, 10);
  h = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
  grid.set(v, 0, 0);
  EXPECT_NE(h.validateAgainst(grid), "");
  ASSERT_TRUE(h.removeVoxel(v));
  EXPECT_EQ(h.validateAgainst(grid), "");
  // Counted: at least a voxel's digit and flag; at most what kept coordinates would cost.
  EXPECT_GT(h.memoryBytes(), h.voxelCount() * 3);
  EXPECT_LT(h.memoryBytes(), h.voxelCount() * 12);
}

TEST(Dph, SeedsGiveDifferentButValidHierarchiesAndTheSameSeedTheSameOne) {
  std::mt19937 rng(77);
  const std::vector<glm::ivec3> voxels = randomVoxels(rng, 20, 0.6);
  DphBuildOptions a, b;
  a.method = b.method = DphBuildMethod::kInsertion;
  a.seed = 1;
  b.seed = 2;
  const auto h1 = DynamicProximityHierarchy::build(voxels, a);
  const auto h1again = DynamicProximityHierarchy::build(voxels, a);
  const auto h2 = DynamicProximityHierarchy::build(voxels, b);
  EXPECT_EQ(h1.validate(), "");
  EXPECT_EQ(h2.validate(), "");
  ASSERT_EQ(h1.levelCount(), h1again.levelCount());
  bool differ = h1.levelCount() != h2.levelCount();
  for (int L = 0; L < h1.levelCount(); ++L) {
    ASSERT_EQ(h1.nodeCount(L), h1again.nodeCount(L));
    for (std::uint32_t i = 0; i < h1.nodeCount(L); ++i) {
      ASSERT_EQ(h1.centre(L, i), h1again.centre(L, i));
    }
    if (L < h2.levelCount() && h1.nodeCount(L) != h2.nodeCount(L)) differ = true;
  }
  EXPECT_TRUE(differ || h1.centre(1, 0) != h2.centre(1, 0));
}

TEST(Dph, EdgeCasesAndBadOptions) {
  const auto empty = DynamicProximityHierarchy::build(std::vector<glm::ivec3>{}, DphBuildOptions{});
  EXPECT_EQ(empty.levelCount(), 0);
  EXPECT_EQ(empty.root(), DynamicProximityHierarchy::kNone);
  EXPECT_EQ(empty.validate(), "");
  const auto single = DynamicProximityHierarchy::build({{4, 5, 6}}, DphBuildOptions{});
  EXPECT_EQ(single.levelCount(), 1);
  EXPECT_EQ(single.root(), 0u);
  DphQueryScratch scratch;
  glm::ivec3 nearest;
  double d;
  EXPECT_TRUE(single.nearestVoxel({0, 0, 0}, scratch, nearest, d));
  EXPECT_EQ(nearest, glm::ivec3(4, 5, 6));

  DphBuildOptions even;
  even.expansionRatio = 4;
  EXPECT_THROW(DynamicProximityHierarchy::build({{0, 0, 0}}, even), InputError);
  DphBuildOptions tiny;
  tiny.expansionRatio = 1;
  EXPECT_THROW(DynamicProximityHierarchy::build({{0, 0, 0}}, tiny), InputError);
  EXPECT_THROW(DynamicProximityHierarchy::build({{1, 1, 1}, {1, 1, 1}}, DphBuildOptions{}),
               InputError);
}

}  // namespace
}  // namespace osteon::geometry
