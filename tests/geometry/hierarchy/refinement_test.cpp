#include "osteon/geometry/hierarchy/refinement.h"

#include <cstring>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/carve.h"
#include "support/shapes.h"

namespace osteon::geometry {
namespace {

bool sameVoxels(const VoxelGrid& a, const VoxelGrid& b) {
  for (int z = 0; z < a.dims().z; ++z)
    for (int y = 0; y < a.dims().y; ++y)
      for (int x = 0; x < a.dims().x; ++x) {
        if (a.fill({x, y, z}) != b.fill({x, y, z}) ||
            a.density({x, y, z}) != b.density({x, y, z})) {
          return false;
        }
      }
  return true;
}

// A sphere of radius 10 mm voxelized at the seed's coarsest size, with its hierarchy and the
// mesh's fine fill.
class RefinementTest : public ::testing::Test {
 protected:
  void SetUp() override {
    mesh_ = test::makeSphere(10.0, 256, 128);
    VoxelizeOptions options;
    options.voxelSizeMm = 1.2;
    grid_ = voxelize(mesh_, options);
    scene_ = std::make_unique<EmbreeScene>(mesh_);
    source_ = FineFillSource::sample(grid_, mesh_, *scene_);
    hierarchy_ = DynamicProximityHierarchy::build(grid_, DphBuildOptions{});
  }
  RefinedVoxels make(int depth, const FineFillSource* source, std::size_t capacity = 4096) {
    RefinementOptions options;
    options.depth = depth;
    options.capacity = capacity;
    return RefinedVoxels(grid_, hierarchy_, source, options);
  }

  TriangleMesh mesh_;
  VoxelGrid grid_;
  std::unique_ptr<EmbreeScene> scene_;
  FineFillSource source_;
  DynamicProximityHierarchy hierarchy_;
  const glm::dvec3 surfacePoint_{10.0, 0.3, 0.2};
  const double outerMm_ = 1.46 + 2 * 0.3;  // 2.92 mm drill, cushion of two level -2 voxels
};

TEST_F(RefinementTest, SubVoxelsSumExactlyToTheirParentAndFollowTheMesh) {
  RefinedVoxels refined = make(2, &source_);
  EXPECT_GT(source_.voxelCount(), 500u);
  const int created = refined.refineAround(surfacePoint_, outerMm_, 0.0);
  ASSERT_GT(created, 10);
  EXPECT_EQ(refined.refinedCount(), std::size_t(created));
  int partial = 0, checked = 0;
  for (int z = 0; z < grid_.dims().z; ++z)
    for (int y = 0; y < grid_.dims().y; ++y)
      for (int x = 0; x < grid_.dims().x; ++x) {
        std::array<Fill, kSubVoxels> fill;
        std::array<Density, kSubVoxels> density;
        if (!refined.subFill({x, y, z}, fill, density)) continue;
        unsigned sum = 0;
        for (Fill f : fill) sum += f;
        ASSERT_EQ(sum, grid_.fill({x, y, z}));
        if (grid_.fill({x, y, z}) == kFillFull) continue;
        ++partial;
        // Sub-voxels clearly inside the sphere are full, clearly outside empty.
        const glm::dvec3 corner = grid_.worldFromGrid(glm::dvec3(x, y, z));
        for (int i = 0; i < kSubVoxels; ++i) {
          const glm::dvec3 c = corner + (glm::dvec3(i % 4, (i / 4) % 4, i / 16) + 0.5) * 0.3;
          const double r = glm::length(c);
          if (r < 10.0 - 0.3) {
            EXPECT_GE(fill[std::size_t(i)], 250) << r;
            ++checked;
          }
          if (r > 10.0 + 0.3) {
            EXPECT_LE(fill[std::size_t(i)], 5) << r;
            ++checked;
          }
          EXPECT_EQ(density[std::size_t(i)] > 0, fill[std::size_t(i)] > 0);
        }
      }
  EXPECT_GT(partial, 3);
  EXPECT_GT(checked, 50);
}

TEST_F(RefinementTest, WithoutTheMeshSubVoxelsInheritTheParentFill) {
  RefinedVoxels refined = make(1, nullptr);
  refined.refineAround(surfacePoint_, outerMm_, 0.0);
  int seen = 0;
  for (int z = 0; z < grid_.dims().z; ++z)
    for (int y = 0; y < grid_.dims().y; ++y)
      for (int x = 0; x < grid_.dims().x; ++x) {
        std::array<Fill, kSubVoxels> fill;
        std::array<Density, kSubVoxels> density;
        if (!refined.subFill({x, y, z}, fill, density)) continue;
        const Fill parent = grid_.fill({x, y, z});
        unsigned sum = 0;
        for (int i = 0; i < 8; ++i) {
          sum += fill[std::size_t(i)];
          EXPECT_NEAR(fill[std::size_t(i)], parent / 8.0, 8.0);  // even split at level -1
        }
        EXPECT_EQ(sum, parent);
        ++seen;
      }
  EXPECT_GT(seen, 0);
  EXPECT_DOUBLE_EQ(refined.sampleSizeMm(), 0.6);
}

TEST_F(RefinementTest, ExpiryRestoresTheGridExactlyAndFreesEverything) {
  const VoxelGrid before = grid_;
  const std::size_t gridBytes = grid_.memoryBytes();
  RefinedVoxels refined = make(2, &source_);
  EXPECT_EQ(refined.bytesInUse(), 0u);
  refined.refineAround(surfacePoint_, outerMm_, 0.0);
  EXPECT_GT(refined.bytesInUse(), 0u);
  // The tool stays for a second, then leaves; nothing expires before the timeout.
  refined.refineAround(surfacePoint_, outerMm_, 1.0);
  EXPECT_EQ(refined.expire(2.9), 0);
  EXPECT_GT(refined.expire(3.1), 0);
  EXPECT_EQ(refined.refinedCount(), 0u);
  EXPECT_EQ(refined.bytesInUse(), 0u);
  grid_.compact();
  EXPECT_TRUE(sameVoxels(before, grid_));
  EXPECT_EQ(grid_.memoryBytes(), gridBytes);
  EXPECT_EQ(hierarchy_.validateAgainst(grid_), "");
}

TEST_F(RefinementTest, VoxelsAQueryOpensStayRefinedAsLongAsItKeepsOpeningThem) {
  // A drill's shaft keeps pushing on the wall the tip refined: the tip refines at the
  // surface point at t = 0 and then works 8 mm away; a query around the first place (the
  // shaft) keeps its voxels alive, voxels nobody reaches expire.
  RefinedVoxels refined = make(2, &source_);
  refined.refineAround(surfacePoint_, outerMm_, 0.0);
  const std::size_t atStart = refined.refinedCount();
  const glm::dvec3 away = surfacePoint_ + glm::dvec3(0.0, 8.0, 0.0);
  for (double t = 1.0; t <= 5.0; t += 1.0) {
    refined.refineAround(away, outerMm_, t);
    int samples = 0;
    refined.forEachSampleInSphere(surfacePoint_, 0.5, [&](const VoxelSample&) { ++samples; });
    EXPECT_GT(samples, 0);
    refined.expire(t);
  }
  // Those the 0.5 mm query opened are alive at t = 5, the rest of the first set are gone.
  int alive = 0;
  for (const glm::ivec3& v : refined.refinedVoxels()) {
    const glm::dvec3 c = grid_.voxelCentreMm(v);
    alive += glm::length(c - surfacePoint_) < 0.5 + 1.1 ? 1 : 0;
  }
  EXPECT_GT(alive, 0);
  EXPECT_LT(refined.refinedCount(), 2 * atStart);
  refined.refineAround(away, outerMm_, 9.0);
  refined.expire(9.0);
  for (const glm::ivec3& v : refined.refinedVoxels()) {
    EXPECT_GT(glm::length(grid_.voxelCentreMm(v) - surfacePoint_), 4.0);  // only near `away`
  }
}

TEST_F(RefinementTest, RemovalAtTheFinestLevelConservesVolumeAndNeverResurrects) {
  RefinedVoxels refined = make(2, &source_);
  const std::uint64_t start = grid_.totalFill();
  const glm::dvec3 tip(9.5, 0.3, 0.2);
  refined.refineAround(tip, outerMm_, 0.0);
  test::Carved removed;
  for (int step = 0; step < 60; ++step) {  // enough steps to wear d = 40 away
    const test::Carved r = test::carveSphere(refined, tip, 1.46);
    removed.removedFill += r.removedFill;
    removed.samplesRemoved += r.samplesRemoved;
    removed.voxelsEmptied += r.voxelsEmptied;
  }
  ASSERT_GT(removed.samplesRemoved, 20u);
  EXPECT_EQ(grid_.totalFill(), start - removed.removedFill);  // exact, in fill units
  EXPECT_EQ(hierarchy_.validateAgainst(grid_), "");
  // Nothing with bone is left inside the drill.
  int inside = 0;
  refined.forEachSampleInSphere(tip, 1.46, [&](const VoxelSample& s) {
    EXPECT_EQ(s.level, -2);
    ++inside;
  });
  EXPECT_EQ(inside, 0);

  // Expire, then refine the same place again: volume unchanged, and still nothing there.
  const std::uint64_t afterDrilling = grid_.totalFill();
  EXPECT_GT(refined.expire(10.0), 0);
  EXPECT_EQ(grid_.totalFill(), afterDrilling);
  EXPECT_GT(refined.refineAround(tip, outerMm_, 20.0), 0);
  EXPECT_EQ(grid_.totalFill(), afterDrilling);
  refined.forEachSampleInSphere(tip, 1.46, [&](const VoxelSample&) { ++inside; });
  EXPECT_EQ(inside, 0) << "removed bone came back";
  refined.expireAll();
  EXPECT_EQ(grid_.totalFill(), afterDrilling);
  EXPECT_GT(refined.bytesInUse(), 0u);  // the removal masks of drilled voxels remain
}

TEST_F(RefinementTest, StaticRemovalActsOnWholeVoxels) {
  RefinedVoxels refined = make(0, &source_);
  EXPECT_EQ(refined.refineAround(surfacePoint_, outerMm_, 0.0), 0);
  const std::uint64_t start = grid_.totalFill();
  test::Carved total;
  for (int step = 0; step < 60; ++step) {
    const test::Carved r = test::carveSphere(refined, {9.0, 0.3, 0.2}, 1.46);
    total.removedFill += r.removedFill;
    total.voxelsEmptied += r.voxelsEmptied;
  }
  EXPECT_GT(total.voxelsEmptied, 0u);
  EXPECT_EQ(grid_.totalFill(), start - total.removedFill);
  EXPECT_EQ(hierarchy_.validateAgainst(grid_), "");
}

TEST_F(RefinementTest, SampleQueryEqualsABruteForceScan) {
  RefinedVoxels refined = make(2, &source_);
  refined.refineAround(surfacePoint_, outerMm_, 0.0);
  refined.refineAround({-3.0, 9.0, 1.0}, outerMm_, 0.0);
  std::mt19937 rng(31337);
  std::uniform_real_distribution<double> pos(-12.0, 12.0);
  std::uniform_real_distribution<double> rad(0.0, 4.0);
  for (int q = 0; q < 200; ++q) {
    // Half of the queries near the refined spots.
    const glm::dvec3 c = q % 2
                             ? glm::dvec3(pos(rng), pos(rng), pos(rng))
                             : surfacePoint_ + glm::dvec3(rad(rng) - 2, rad(rng) - 2, rad(rng) - 2);
    const double r = rad(rng);
    std::uint64_t fillSeen = 0;
    int count = 0;
    refined.forEachSampleInSphere(c, r, [&](const VoxelSample& s) {
      fillSeen += s.fill;
      ++count;
    });
    std::uint64_t fillExpected = 0;
    int countExpected = 0;
    for (int z = 0; z < grid_.dims().z; ++z)
      for (int y = 0; y < grid_.dims().y; ++y)
        for (int x = 0; x < grid_.dims().x; ++x) {
          const glm::ivec3 v(x, y, z);
          if (grid_.fill(v) == 0) continue;
          std::array<Fill, kSubVoxels> fill;
          std::array<Density, kSubVoxels> density;
          if (!refined.subFill(v, fill, density)) {
            if (glm::length(grid_.voxelCentreMm(v) - c) <= r) {
              fillExpected += grid_.fill(v);
              ++countExpected;
            }
            continue;
          }
          const glm::dvec3 corner = grid_.worldFromGrid(glm::dvec3(v));
          for (int i = 0; i < kSubVoxels; ++i) {
            const glm::dvec3 sc = corner + (glm::dvec3(i % 4, (i / 4) % 4, i / 16) + 0.5) * 0.3;
            if (fill[std::size_t(i)] > 0 && glm::length(sc - c) <= r) {
              fillExpected += fill[std::size_t(i)];
              ++countExpected;
            }
          }
        }
    ASSERT_EQ(count, countExpected) << "query " << q;
    ASSERT_EQ(fillSeen, fillExpected) << "query " << q;
  }
}

// A shell around a drifting, turning segment (a shaft levered in its hole) through a query
// cache: the voxels skipped while their slack lasts hide no sample, so every query gives the
// samples of the same query without the cache, in the same order, while bone is cut between.
TEST_F(RefinementTest, ShellQueriesThroughACacheSkipNoSample) {
  RefinedVoxels refined = make(2, &source_);
  const glm::dvec3 axis = glm::normalize(glm::dvec3(-1.0, 0.2, 0.1));
  refined.refineAround(surfacePoint_ + 2.0 * axis, 6.0, 0.0);
  ASSERT_GT(refined.refinedCount(), 100u);
  DphNearCache cache(1.2, DphNearCache::capacityFor(5.0, 2.5 + 1.04 + 1.2, 1.2), 64);
  cache.reserveFor(hierarchy_);
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> wobble(-0.004, 0.004);
  glm::dvec3 a = surfacePoint_ + 0.5 * axis, b = a + 5.0 * axis;
  std::size_t inShell = 0, queries = 0;
  const auto open = [](const glm::dvec3&, double) { return true; };
  for (int step = 0; step < 1500; ++step) {
    // The far end sweeps a circle of 1.5 mm, the near end drifts: samples enter and leave.
    const double phase = 0.004 * step;
    a += glm::dvec3(wobble(rng), wobble(rng), wobble(rng));
    b = a + 5.0 * axis + 1.5 * glm::dvec3(0.0, std::cos(phase) - 1.0, std::sin(phase));
    std::vector<std::pair<int, std::uint64_t>> plain, cached;
    const auto record = [](std::vector<std::pair<int, std::uint64_t>>& out) {
      return [&out](const VoxelSample& s, const glm::dvec3& toCore) {
        std::uint64_t bits = 0;
        const double q = toCore.x + 3.0 * toCore.y + 7.0 * toCore.z;
        std::memcpy(&bits, &q, sizeof bits);
        out.push_back({int(s.fill), bits});
      };
    };
    // Every fifth query asks the same cache for a wider shell: a slack measured against the
    // narrow one must not skip for it. Midway the cache is replaced by a new one.
    const double outer = step % 5 == 4 ? 2.5 : 1.5;
    if (step == 700) {
      cache = DphNearCache(1.2, DphNearCache::capacityFor(5.0, 2.5 + 1.04 + 1.2, 1.2), 64);
      cache.reserveFor(hierarchy_);
    }
    refined.forEachSampleInShell(a, b, 0.9, outer, nullptr, open, record(plain));
    refined.forEachSampleInShell(a, b, 0.9, outer, &cache, open, record(cached));
    ASSERT_EQ(cached, plain) << "step " << step;
    inShell += plain.size();
    ++queries;
    if (step % 50 == 49) test::carve(refined, test::Cut{a, a + 0.8 * axis, 1.0, false}, 1000);
  }
  EXPECT_GT(inShell, queries * 5);  // the shell met bone throughout
  EXPECT_GT(cache.reuses(), 600u);
}

TEST_F(RefinementTest, AFullPoolLeavesVoxelsUnrefinedAndSaysSo) {
  RefinedVoxels refined = make(2, &source_, 4);
  refined.refineAround(surfacePoint_, outerMm_, 0.0);
  EXPECT_EQ(refined.refinedCount(), 4u);
  EXPECT_GT(refined.poolExhausted(), 0u);
}

// Each names the option field and its value (the front ends turn fields into their flags).
TEST_F(RefinementTest, BadOptionsAreInputErrors) {
  const auto message = [this](const RefinementOptions& options) -> std::string {
    try {
      RefinedVoxels refined(grid_, hierarchy_, nullptr, options);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  RefinementOptions options;
  options.depth = 3;
  EXPECT_EQ(message(options).rfind("RefinementOptions::depth 3: ", 0), 0u) << message(options);
  options.depth = 2;
  options.timeoutS = 0.0;
  EXPECT_EQ(message(options).rfind("RefinementOptions::timeoutS 0: ", 0), 0u) << message(options);
  options.timeoutS = 2.0;
  options.capacity = 0;
  EXPECT_EQ(message(options).rfind("RefinementOptions::capacity 0: ", 0), 0u) << message(options);
}

}  // namespace
}  // namespace osteon::geometry
