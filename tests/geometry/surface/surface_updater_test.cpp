#include "osteon/geometry/surface/surface_updater.h"

#include <algorithm>
#include <map>
#include <random>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/carve.h"
#include "support/shapes.h"

namespace osteon::geometry {
namespace {

// Compares two surfaces as sets: every vertex of `b` must sit within 1e-6 mm of one vertex
// of `a` (one to one), and the triangles, as vertex triples up to rotation, must be the same.
std::string compareSurfaces(const SurfaceMesh& a, const SurfaceMesh& b) {
  if (a.vertexCount() != b.vertexCount()) {
    return "vertices " + std::to_string(a.vertexCount()) + " vs " + std::to_string(b.vertexCount());
  }
  if (a.triangleCount() != b.triangleCount()) {
    return "triangles " + std::to_string(a.triangleCount()) + " vs " +
           std::to_string(b.triangleCount());
  }
  const double cell = 1e-3;
  std::map<std::array<long long, 3>, std::vector<std::uint32_t>> buckets;
  const auto keyOf = [&](const glm::dvec3& p) {
    return std::array<long long, 3>{(long long)std::floor(p.x / cell),
                                    (long long)std::floor(p.y / cell),
                                    (long long)std::floor(p.z / cell)};
  };
  for (std::uint32_t i = 0; i < a.vertexCount(); ++i) buckets[keyOf(a.positionsMm[i])].push_back(i);
  std::vector<std::uint32_t> toA(b.vertexCount());
  std::vector<char> used(a.vertexCount(), 0);
  for (std::uint32_t i = 0; i < b.vertexCount(); ++i) {
    const glm::dvec3 p = b.positionsMm[i];
    const auto k = keyOf(p);
    std::int64_t found = -1;
    for (int dz = -1; dz <= 1 && found < 0; ++dz)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dx = -1; dx <= 1 && found < 0; ++dx) {
          const auto it = buckets.find({k[0] + dx, k[1] + dy, k[2] + dz});
          if (it == buckets.end()) continue;
          for (std::uint32_t j : it->second) {
            if (!used[j] && glm::length(a.positionsMm[j] - p) <= 1e-6) {
              found = j;
              break;
            }
          }
        }
    if (found < 0) return "vertex " + std::to_string(i) + " has no match within 1e-6 mm";
    used[std::size_t(found)] = 1;
    toA[i] = std::uint32_t(found);
  }
  const auto canonical = [](glm::u32vec3 t) {
    while (t.x > t.y || t.x > t.z) t = {t.y, t.z, t.x};
    return std::array<std::uint32_t, 3>{t.x, t.y, t.z};
  };
  std::vector<std::array<std::uint32_t, 3>> ta, tb;
  for (const glm::u32vec3& t : a.triangles) ta.push_back(canonical(t));
  for (const glm::u32vec3& t : b.triangles) tb.push_back(canonical({toA[t.x], toA[t.y], toA[t.z]}));
  std::sort(ta.begin(), ta.end());
  std::sort(tb.begin(), tb.end());
  if (ta != tb) return "triangle sets differ";
  for (std::uint32_t i = 0; i < b.vertexCount(); ++i) {
    if (glm::length(a.normals[toA[i]] - b.normals[i]) > 1e-6)
      return "normal " + std::to_string(i) + " differs";
  }
  return "";
}

// Random drilling edits, each followed by an update that must equal a full extraction.
void drillAndCompare(VoxelGrid& grid, const TriangleMesh& surface, int depth,
                     const SurfaceOptions& options, int steps, std::uint32_t seed) {
  auto hierarchy = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
  RefinementOptions ro;
  ro.depth = depth;
  RefinedVoxels refined(grid, hierarchy, nullptr, ro);
  grid.clearDirty();
  SurfaceUpdater updater(grid, options);
  ASSERT_EQ(compareSurfaces(extractSurface(grid, options), updater.mesh()), "");
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, surface.vertexCount() - 1);
  std::uniform_int_distribution<int> strokes(1, 60);
  for (int step = 0; step < steps; ++step) {
    const glm::dvec3 at = surface.positionsMm[pick(rng)];
    refined.refineAround(at, 1.46 + 0.6, double(step));
    const int n = strokes(rng);  // sometimes a scratch, sometimes a hole
    for (int k = 0; k < n; ++k) test::carveSphere(refined, at, 1.46);
    if (step % 3 == 2) refined.expire(double(step) + 10.0);
    const SurfaceUpdater::UpdateStats stats = updater.update(grid.dirtyBricks());
    grid.clearDirty();
    ASSERT_EQ(updater.validate(), "") << "step " << step;
    ASSERT_EQ(compareSurfaces(extractSurface(grid, options), updater.mesh()), "")
        << "step " << step << " (" << stats.cellBricks << " cell bricks)";
  }
}

TEST(SurfaceUpdater, DrillingEditsEqualAFullExtractionAfterEveryStep) {
  const HumerusModel model = buildHumerusModel();
  VoxelizeOptions options;
  options.voxelSizeMm = 1.2;
  VoxelGrid grid = voxelize(model.mesh, options);
  drillAndCompare(grid, model.mesh, 0, SurfaceOptions{}, 40, 11);
}

TEST(SurfaceUpdater, SubVoxelRemovalAndTaubinSmoothingAlsoMatch) {
  // Level -2 removal changes parent fills a little at a time; Taubin and more passes widen
  // the smoothing's reach.
  const TriangleMesh sphere = test::makeSphere(10.0, 128, 64);
  VoxelizeOptions options;
  options.voxelSizeMm = 0.9;
  VoxelGrid grid = voxelize(sphere, options);
  SurfaceOptions taubin;
  taubin.taubin = true;
  taubin.smoothIterations = 6;
  drillAndCompare(grid, sphere, 2, taubin, 30, 12);
}

TEST(SurfaceUpdater, DrillingThroughAThinWallAndEmptyingBricks) {
  // A 3 mm plate drilled through repeatedly: surfaces vanish and appear, bricks empty.
  const TriangleMesh plate = test::makeBox({-12, -12, -1.5}, {12, 12, 1.5});
  VoxelizeOptions options;
  options.voxelSizeMm = 0.5;
  VoxelGrid grid = voxelize(plate, options);
  drillAndCompare(grid, plate, 1, SurfaceOptions{}, 40, 13);
}

TEST(SurfaceUpdater, FullExtractionAgreesOnGridsOfSizesAroundABrick) {
  // The full extractor reads most blocks through the scan's bricks and rows (dense ones) and
  // clips the rest at the grid's end; the updater reads every block its own way. Grids of 1,
  // 7, 8, 9 and 17 voxels per axis put every kind of block at the border: noise, a full
  // brick, and a uniform brick of a fill between empty and full (whose block is not dense).
  std::mt19937 rng(21);
  std::uniform_int_distribution<int> noise(0, int(kFillFull));
  const int sizes[] = {1, 7, 8, 9, 17};
  for (int sx : sizes)
    for (int sy : sizes)
      for (int sz : sizes) {
        VoxelGrid grid({sx, sy, sz}, glm::dvec3(0.0), 1.0);
        for (int z = 0; z < sz; ++z)
          for (int y = 0; y < sy; ++y)
            for (int x = 0; x < sx; ++x) {
              if (x < 8 && y < 8 && z < 8 && sx >= 16)
                continue;  // left to the uniform values below
              grid.set({x, y, z}, Fill(noise(rng) < int(kFillFull) / 2 ? 0 : noise(rng)), 5);
            }
        if (sx >= 16)
          grid.setBrickUniform(grid.brickIndex({0, 0, 0}),
                               sy >= 16 ? kFillFull : Fill(kFillHalf + 7), 5);
        SurfaceOptions options;
        options.smoothIterations = (sx + sy + sz) % 3;
        SurfaceUpdater updater(grid, options);
        ASSERT_EQ(compareSurfaces(extractSurface(grid, options), updater.mesh()), "")
            << sx << " x " << sy << " x " << sz;
      }
}

// The first extraction runs in parallel; it must be, slot for slot and bit for bit, what the
// serial update of every brick gives: an updater started on an empty grid, then updated
// after the grid is filled, takes that serial path.
void expectFirstExtractionIsTheSerialOne(const VoxelGrid& grid, const SurfaceOptions& options) {
  const SurfaceUpdater parallel(grid, options);
  VoxelGrid filled(grid.dims(), grid.originMm(), grid.voxelSizeMm());
  SurfaceUpdater serial(filled, options);
  filled = grid;
  std::vector<std::size_t> all(grid.brickCount());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  serial.update(all);
  const SurfaceMesh a = parallel.mesh(), b = serial.mesh();
  ASSERT_GT(a.triangleCount(), 0u);
  ASSERT_EQ(a.positionsMm, b.positionsMm);
  ASSERT_EQ(a.normals, b.normals);
  ASSERT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.brickRanges.size(), b.brickRanges.size());
  EXPECT_EQ(parallel.validate(), "");
}

TEST(SurfaceUpdater, TheParallelFirstExtractionIsTheSerialOne) {
  VoxelizeOptions voxelizing;
  voxelizing.voxelSizeMm = 0.9;
  const VoxelGrid humerus = voxelize(buildHumerusModel().mesh, voxelizing);
  for (const int iterations : {0, 1, 2}) {
    SurfaceOptions options;
    options.smoothIterations = iterations;
    expectFirstExtractionIsTheSerialOne(humerus, options);
  }
  SurfaceOptions taubin;
  taubin.taubin = true;
  taubin.smoothIterations = 4;
  expectFirstExtractionIsTheSerialOne(humerus, taubin);
  // Noise: loops of five and six vertices (centres) in numbers.
  VoxelGrid noisy({19, 17, 23}, glm::dvec3(1.0, -2.0, 0.5), 0.7);
  std::mt19937 rng(8);
  std::uniform_int_distribution<int> fill(0, int(kFillFull));
  for (int z = 0; z < 23; ++z)
    for (int y = 0; y < 17; ++y)
      for (int x = 0; x < 19; ++x) noisy.set({x, y, z}, Fill(fill(rng)), 2);
  expectFirstExtractionIsTheSerialOne(noisy, SurfaceOptions{});
}

TEST(SurfaceUpdater, NothingChangedNothingDone) {
  const TriangleMesh sphere = test::makeSphere(5.0, 64, 32);
  VoxelizeOptions options;
  options.voxelSizeMm = 0.5;
  VoxelGrid grid = voxelize(sphere, options);
  SurfaceUpdater updater(grid);
  const SurfaceUpdater::UpdateStats stats = updater.update({0, 1, 2});
  EXPECT_EQ(stats.verticesTouched, 0u);
  EXPECT_EQ(compareSurfaces(extractSurface(grid), updater.mesh()), "");
  SurfaceOptions bad;
  bad.smoothIterations = -2;
  EXPECT_THROW(SurfaceUpdater(grid, bad), InputError);
}

// The first extraction from the grid as it was, on a thread of its own while the grid is
// drilled; the update with the bricks changed meanwhile then equals a full extraction. And a
// surface that keeps growing past its first extraction's slots (every growth a new page, none
// a copy) stays equal to it.
TEST(SurfaceUpdater, BuiltFromTheGridAsItWasWhileItChangesThenCaughtUp) {
  const HumerusModel model = buildHumerusModel();
  VoxelizeOptions options;
  options.voxelSizeMm = 0.9;
  const VoxelGrid asItWas = voxelize(model.mesh, options);
  VoxelGrid grid = asItWas;
  grid.clearDirty();
  std::unique_ptr<SurfaceUpdater> updater;
  std::thread build(
      [&] { updater = std::make_unique<SurfaceUpdater>(grid, SurfaceOptions{}, asItWas); });
  // Meanwhile: 60 tunnels of removed voxels, each a few mm long, anywhere in the bone.
  std::mt19937 rng(37);
  std::uniform_int_distribution<int> at(0, 1 << 30);
  const glm::ivec3 d = grid.dims();
  for (int k = 0; k < 60; ++k) {
    const glm::ivec3 c(at(rng) % d.x, at(rng) % d.y, at(rng) % d.z);
    for (int i = -3; i <= 3; ++i)
      for (int j = -1; j <= 1; ++j)
        for (int l = -1; l <= 1; ++l)
          if (grid.inBounds(c + glm::ivec3(i, j, l))) grid.set(c + glm::ivec3(i, j, l), 0, 0);
  }
  build.join();
  EXPECT_EQ(compareSurfaces(extractSurface(asItWas), updater->mesh()), "");
  updater->update(grid.dirtyBricks());
  grid.clearDirty();
  EXPECT_EQ(compareSurfaces(extractSurface(grid), updater->mesh()), "");
  EXPECT_EQ(updater->validate(), "");
  // Growth: a hollow inside the bone is new surface, far past a page of slots in all.
  const std::size_t firstSlots = updater->takeChanges().slotCount;
  std::size_t slots = firstSlots;
  for (int k = 0; k < 20000 && slots < firstSlots + 20000; ++k) {
    const glm::ivec3 c(at(rng) % d.x, at(rng) % d.y, at(rng) % d.z);
    if (grid.fill(c) != kFillFull) continue;
    grid.set(c, 0, 0);
    updater->update(grid.dirtyBricks());
    grid.clearDirty();
    slots = updater->takeChanges().slotCount;
  }
  EXPECT_GT(slots, firstSlots + 16384);
  EXPECT_EQ(compareSurfaces(extractSurface(grid), updater->mesh()), "");
  EXPECT_EQ(updater->validate(), "");
  const SurfaceUpdater::Memory memory = updater->memory();
  EXPECT_GT(memory.vertices, updater->vertexCount() * 24);
  EXPECT_GT(memory.cellBricks, 0u);
  EXPECT_EQ(memory.total(),
            memory.cellBricks + memory.triangles + memory.vertices + memory.loops + memory.tables);
  VoxelGrid other({4, 4, 4}, glm::dvec3(0.0), 0.9);
  EXPECT_THROW(SurfaceUpdater(grid, SurfaceOptions{}, other), std::logic_error);
}

}  // namespace
}  // namespace osteon::geometry
