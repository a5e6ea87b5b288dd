#include "osteon/geometry/voxels/voxelizer.h"

#include "osteon/core/error.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "support/shapes.h"
// The ray caster is internal to the geometry library; its packet path is checked here.
#include <cmath>
#include <filesystem>
#include <limits>

#include <gtest/gtest.h>

#include "../../../geometry/src/voxels/column_ray.h"

namespace osteon::geometry {
namespace {

constexpr double kPi = 3.14159265358979323846;

double relativeError(double value, double reference) {
  return std::abs(value - reference) / std::abs(reference);
}

VoxelGrid voxelizeAt(const TriangleMesh& mesh, double voxelSizeMm, bool robust = false,
                     VoxelizeStats* stats = nullptr) {
  VoxelizeOptions options;
  options.voxelSizeMm = voxelSizeMm;
  options.robust = robust;
  return voxelize(mesh, options, stats);
}

// Drops the triangles whose centroid direction from the centre lies within `angleDeg` of
// `axis`: a sphere with a round hole.
TriangleMesh punchHole(const TriangleMesh& sphere, glm::dvec3 axis, double angleDeg) {
  TriangleMesh holed = sphere;
  holed.triangles.clear();
  const double cosLimit = std::cos(angleDeg * kPi / 180.0);
  for (const glm::u32vec3& t : sphere.triangles) {
    const glm::dvec3 c =
        (sphere.positionsMm[t.x] + sphere.positionsMm[t.y] + sphere.positionsMm[t.z]) / 3.0;
    if (glm::dot(glm::normalize(c), glm::normalize(axis)) < cosLimit) holed.triangles.push_back(t);
  }
  return holed;
}

// Every voxel's density against its own exact distance query: cortical exactly when the
// centre is within the shell, cancellous otherwise, none without bone. The density pass
// settles most voxels from bounds (brick centre, visited neighbours) and answers the rest
// from the triangles gathered near their brick; this checks that neither ever decides a
// voxel differently from its own Embree distance query.
void expectDensityFromExactDistances(const TriangleMesh& mesh, double voxelSizeMm) {
  VoxelizeOptions options;
  options.voxelSizeMm = voxelSizeMm;
  VoxelizeStats stats;
  const VoxelGrid g = voxelize(mesh, options, &stats);
  const EmbreeScene scene(mesh);
  const double shell = options.density.corticalThicknessMm;
  std::uint64_t mismatches = 0, cortical = 0, bone = 0;
  for (int z = 0; z < g.dims().z; ++z)
    for (int y = 0; y < g.dims().y; ++y)
      for (int x = 0; x < g.dims().x; ++x) {
        const Density d = g.density({x, y, z});
        if (g.fill({x, y, z}) == 0) {
          mismatches += d != 0 ? 1 : 0;
          continue;
        }
        ++bone;
        const double distance = scene.distanceWithin(g.voxelCentreMm({x, y, z}), shell + 1.0);
        const bool expectCortical = distance >= 0.0 && distance <= shell;
        const Density expected =
            expectCortical ? options.density.corticalDensity : options.density.cancellousDensity;
        mismatches += d != expected ? 1 : 0;
        cortical += expectCortical ? 1 : 0;
      }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(cortical, stats.density.corticalVoxels);
  EXPECT_EQ(bone, stats.density.corticalVoxels + stats.density.cancellousVoxels);
  EXPECT_LT(stats.density.distanceQueries, bone / 2);  // bounds settle most voxels
}

// The voxelizer casts each column's rays as Embree packets: every ray must give what the
// single-ray cast gives (same outcome, attempts and intervals, bit for bit), or the grid
// would change. Columns along each axis of the grid, a ray bundle of 4 x 4 and of 3 x 3.
void expectPacketsMatchSingleRays(const TriangleMesh& mesh, double voxelSizeMm, int stride) {
  const VoxelGrid layout = makeGridFor(mesh, voxelSizeMm);
  const EmbreeScene scene(mesh);
  const int outwardSign = detail::outwardSignOf(mesh);
  const glm::ivec3 dims = layout.dims();
  const double vs = voxelSizeMm;
  const glm::dvec3 origin = layout.originMm();
  std::uint64_t rays = 0, withHits = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    detail::ColumnRay single(scene, axis, outwardSign, origin[axis] - vs, (dims[axis] + 2) * vs,
                             std::min(1e-4, 1e-3 * vs));
    detail::ColumnRay packet(scene, axis, outwardSign, origin[axis] - vs, (dims[axis] + 2) * vs,
                             std::min(1e-4, 1e-3 * vs));
    for (int R : {4, 3}) {
      for (int iv = 0; iv < dims[v]; iv += stride)
        for (int iu = 0; iu < dims[u]; iu += stride) {
          double us[detail::ColumnRay::kPacket], vs2[detail::ColumnRay::kPacket];
          const int count = R * R;
          for (int i = 0; i < count; ++i) {
            us[i] = origin[u] + (iu + (i % R + 0.5 + 0.0061803) / R) * vs;
            vs2[i] = origin[v] + (iv + (i / R + 0.5 + 0.0041421) / R) * vs;
          }
          std::vector<detail::Interval> packed[detail::ColumnRay::kPacket];
          detail::RayOutcome outcomes[detail::ColumnRay::kPacket];
          int attempts[detail::ColumnRay::kPacket];
          packet.castPacket(count, us, vs2, 2e-3 * vs / R, true, packed, outcomes, attempts);
          for (int i = 0; i < count; ++i) {
            std::vector<detail::Interval> intervals;
            int singleAttempts = 0;
            const detail::RayOutcome outcome =
                single.cast(us[i], vs2[i], 2e-3 * vs / R, intervals, singleAttempts);
            if (outcome == detail::RayOutcome::Unresolved) {
              detail::pairByParity(single.hits(), intervals);
            }
            ++rays;
            withHits += intervals.empty() ? 0u : 1u;
            ASSERT_EQ(int(outcomes[i]), int(outcome))
                << "axis " << axis << " column " << iu << ", " << iv;
            ASSERT_EQ(attempts[i], singleAttempts);
            ASSERT_EQ(packed[i].size(), intervals.size());
            for (std::size_t k = 0; k < intervals.size(); ++k) {
              ASSERT_EQ(packed[i][k].t0, intervals[k].t0);
              ASSERT_EQ(packed[i][k].t1, intervals[k].t1);
            }
          }
        }
    }
  }
  EXPECT_GT(withHits, rays / 4);  // the comparison saw the bone, not only empty padding
}

TEST(Voxelizer, RayPacketsGiveWhatSingleRaysGiveOnTheBuiltInHumerus) {
  expectPacketsMatchSingleRays(buildHumerusModel().mesh, 0.9, 2);
}

TEST(Voxelizer, SphereBoxTorusVolumesWithinHalfAPercentAtRadiusOver20) {
  const double r = 10.0;
  const TriangleMesh sphere = test::makeSphere(r, 512, 256);
  const VoxelGrid s = voxelizeAt(sphere, r / 20.0);
  EXPECT_LT(relativeError(s.filledVolumeMm3(), 4.0 / 3.0 * kPi * r * r * r), 0.005);

  // A box not aligned with any voxel boundary; "radius" = half its smallest side.
  const TriangleMesh box = test::makeBox({-7.31, -2.17, 0.443}, {5.07, 8.91, 13.3});
  const VoxelGrid b = voxelizeAt(box, 0.5 * (8.91 + 2.17) / 20.0);
  EXPECT_LT(relativeError(b.filledVolumeMm3(), 12.38 * 11.08 * 12.857), 0.005);

  const double major = 10.0, minor = 4.0;
  const TriangleMesh torus = test::makeTorus(major, minor, 512, 256);
  const VoxelGrid t = voxelizeAt(torus, minor / 20.0);
  EXPECT_LT(relativeError(t.filledVolumeMm3(), 2.0 * kPi * kPi * major * minor * minor), 0.005);
}

TEST(Voxelizer, FillIsExactForAVoxelAlignedBoxAndFractionalAtItsFaces) {
  // Voxel size 1 and a box of integer size: the grid centres the box, so faces fall on voxel
  // boundaries (odd extents give half offsets; pick extents for which they fall on them).
  const TriangleMesh box = test::makeBox({0, 0, 0}, {4, 6, 8});
  const VoxelGrid g = voxelizeAt(box, 1.0);
  EXPECT_EQ(g.dims(), glm::ivec3(6, 8, 10));  // extent + one voxel of padding each side
  EXPECT_EQ(g.countVoxels(kFillFull), 4u * 6u * 8u);
  EXPECT_EQ(g.countVoxels(1), 4u * 6u * 8u);
  EXPECT_EQ(g.fill({0, 0, 0}), 0);
  EXPECT_EQ(g.fill({1, 1, 1}), kFillFull);

  // Shift by a quarter voxel in z: the top and bottom layers become partly full.
  const TriangleMesh shifted = test::makeBox({0, 0, 0.25}, {4, 6, 7.75});
  const VoxelGrid h = voxelizeAt(shifted, 1.0);
  EXPECT_EQ(h.countVoxels(kFillFull), 4u * 6u * 6u);
  EXPECT_NEAR(h.fill({2, 3, 1}), 0.75 * kFillFull, kFillPerStep);  // layer [0.25, 1) of voxel 1
  EXPECT_NEAR(h.filledVolumeMm3(), 4 * 6 * 7.5, 0.1);              // 0.75 quantised to 191/255
  // Fresh fills sit on the voxelizer's 1/255 steps.
  EXPECT_EQ(h.fill({2, 3, 1}) % kFillPerStep, 0);
}

TEST(Voxelizer, GridIsPaddedAndOnTheWorldLattice) {
  const TriangleMesh sphere = test::makeSphere(5.0, 64, 32, {100, -50, 7});
  const VoxelGrid g = voxelizeAt(sphere, 0.7);
  const Aabb box = bounds(sphere);
  for (int c = 0; c < 3; ++c) {
    const double below = box.minMm[c] - g.originMm()[c];
    const double above = g.worldFromGrid(glm::dvec3(g.dims()))[c] - box.maxMm[c];
    EXPECT_GE(below, 0.7 - 1e-9);
    EXPECT_GE(above, 0.7 - 1e-9);
    EXPECT_LT(below, 1.4 + 1e-9);
    EXPECT_LT(above, 1.4 + 1e-9);
    // Voxel faces on multiples of the voxel size.
    const double k = g.originMm()[c] / 0.7;
    EXPECT_NEAR(k, std::round(k), 1e-9);
  }
  // The outermost layer holds nothing.
  for (int x = 0; x < g.dims().x; ++x)
    for (int y = 0; y < g.dims().y; ++y) EXPECT_EQ(g.fill({x, y, 0}), 0);
}

TEST(Voxelizer, GridsOfHalvedSizesNest) {
  // A 1.2 mm voxel's 4 x 4 x 4 sub-voxels are the 0.3 mm grid's voxels: static and dynamic
  // forces at 0.3 mm sample the same points.
  const TriangleMesh sphere = test::makeSphere(5.0, 64, 32, {13.37, -4.2, 7.9});
  const VoxelGrid coarse = voxelizeAt(sphere, 1.2);
  const VoxelGrid fine = voxelizeAt(sphere, 0.3);
  for (int c = 0; c < 3; ++c) {
    const double offset = (coarse.originMm()[c] - fine.originMm()[c]) / 0.3;
    EXPECT_NEAR(offset, std::round(offset), 1e-9);
  }
}

TEST(Voxelizer, InwardMeshesAndOverlappingShellsGiveTheSolid) {
  TriangleMesh inward = test::makeSphere(8.0, 128, 64);
  for (glm::u32vec3& t : inward.triangles) std::swap(t.y, t.z);
  const double sphereVolume = 4.0 / 3.0 * kPi * 512.0;
  EXPECT_LT(relativeError(voxelizeAt(inward, 0.4).filledVolumeMm3(), sphereVolume), 0.005);

  // Two spheres in one soup, overlapping: parity alone would hollow out the lens between
  // them; the winding walk keeps it.
  TriangleMesh pair = test::makeSphere(8.0, 128, 64);
  const TriangleMesh second = test::makeSphere(8.0, 128, 64, {8.0, 0, 0});
  const auto offset = std::uint32_t(pair.positionsMm.size());
  pair.positionsMm.insert(pair.positionsMm.end(), second.positionsMm.begin(),
                          second.positionsMm.end());
  for (glm::u32vec3 t : second.triangles) pair.triangles.push_back(t + offset);
  // Union of two spheres of radius R at distance d: 2 V - lens.
  const double R = 8.0, d = 8.0;
  const double lens = kPi * (4 * R + d) * (2 * R - d) * (2 * R - d) / 12.0;
  VoxelizeStats stats;
  const VoxelGrid g = voxelizeAt(pair, 0.4, false, &stats);
  EXPECT_GT(stats.raysWinding, 0u);
  EXPECT_LT(relativeError(g.filledVolumeMm3(), 2 * sphereVolume - lens), 0.005);
}

TEST(Voxelizer, RobustModeRecoversASphereWithAMissingPatch) {
  const double r = 10.0;
  const double exact = 4.0 / 3.0 * kPi * r * r * r;
  // The hole faces an oblique direction so every axis has rays that pass through it.
  const TriangleMesh holed = punchHole(test::makeSphere(r, 256, 128), {1, 1, 1}, 20.0);
  ASSERT_GT(analyzeTopology(holed).borderEdges, 0u);

  VoxelizeStats plainStats;
  const double plain = voxelizeAt(holed, 0.5, false, &plainStats).filledVolumeMm3();
  EXPECT_GT(plainStats.raysUnresolved, 0u);
  EXPECT_GT(relativeError(plain, exact), 0.02) << "the hole should hurt single-axis parity";

  VoxelizeStats stats;
  const double robust = voxelizeAt(holed, 0.5, true, &stats).filledVolumeMm3();
  EXPECT_LT(relativeError(robust, exact), 0.02);
  EXPECT_GT(stats.disagreeingVoxels + stats.abstainedColumns, 0u);

  // On an intact mesh all three axes agree.
  VoxelizeStats clean;
  const TriangleMesh sphere = test::makeSphere(r, 256, 128);
  const double v = voxelizeAt(sphere, 0.5, true, &clean).filledVolumeMm3();
  EXPECT_LT(relativeError(v, exact), 0.005);
  EXPECT_EQ(clean.disagreeingVoxels, 0u);
  EXPECT_EQ(clean.raysUnresolved, 0u);
}

TEST(Voxelizer, DensityRuleSeparatesCorticalShellFromCancellousCore) {
  const TriangleMesh sphere = test::makeSphere(10.0, 256, 128);
  VoxelizeOptions options;
  options.voxelSizeMm = 0.5;
  options.density.corticalThicknessMm = 2.0;
  options.density.corticalDensity = 50;
  options.density.cancellousDensity = 7;
  VoxelizeStats stats;
  const VoxelGrid g = voxelize(sphere, options, &stats);
  const glm::ivec3 centre = g.voxelFromWorld({0, 0, 0});
  EXPECT_EQ(g.density(centre), 7);
  EXPECT_EQ(g.density(g.voxelFromWorld({9.2, 0.1, 0.1})), 50);
  EXPECT_EQ(g.density(g.voxelFromWorld({0.1, 0.1, 7.6})), 7);
  EXPECT_EQ(g.density(g.voxelFromWorld({0.1, 0.1, 8.4})), 50);
  EXPECT_EQ(g.density({0, 0, 0}), 0);
  // Every voxel with bone has a density, every empty one none, and a voxel is cortical
  // exactly when its centre lies within 2 mm of the (finely tessellated) sphere.
  std::uint64_t presenceMismatches = 0, classMismatches = 0, cortical = 0;
  for (int z = 0; z < g.dims().z; ++z)
    for (int y = 0; y < g.dims().y; ++y)
      for (int x = 0; x < g.dims().x; ++x) {
        const bool bone = g.fill({x, y, z}) > 0;
        const Density d = g.density({x, y, z});
        if (bone != (d > 0)) ++presenceMismatches;
        if (!bone) continue;
        const double rho = glm::length(g.voxelCentreMm({x, y, z}));
        const bool expectCortical = std::abs(rho - 10.0) <= 2.0;
        if (expectCortical != (d == 50)) ++classMismatches;
        cortical += d == 50 ? 1 : 0;
      }
  EXPECT_EQ(presenceMismatches, 0u);
  EXPECT_EQ(cortical, stats.density.corticalVoxels);
  EXPECT_LE(classMismatches, cortical / 1000);  // only centres at 8 mm +- tessellation error
}

TEST(Voxelizer, DensityOfEveryVoxelIsItsExactDistanceRuleOnTheBuiltInHumerus) {
  // At 0.45 mm a brick's triangles are gathered once and scanned; at 0.9 mm (below) each
  // voxel asks Embree: both paths are checked.
  expectDensityFromExactDistances(buildHumerusModel().mesh, 0.45);
}

TEST(Voxelizer, PrecisionHoldsFarFromTheOriginAndAtTinyScales) {
  // Embree works in floats: the scene is stored around its own centre, so a unit cube at
  // 1e5 mm voxelizes as exactly as one at the origin.
  const TriangleMesh far = test::makeBox({1e5, 1e5, 1e5}, {1e5 + 1, 1e5 + 1, 1e5 + 1});
  const VoxelGrid g = voxelizeAt(far, 0.01);
  EXPECT_NEAR(g.filledVolumeMm3(), 1.0, 1e-3);
  EXPECT_EQ(g.fill({0, 50, 50}), 0);  // the padding stays empty
  // A 1e-4 mm cube at 1e-5 mm voxels (the hit tolerance scales with the voxel).
  const TriangleMesh tiny = test::makeBox({0, 0, 0}, {1e-4, 1e-4, 1e-4});
  EXPECT_NEAR(voxelizeAt(tiny, 1e-5).filledVolumeMm3(), 1e-12, 1e-14);
}

TEST(Voxelizer, AnInvertedComponentIsStillSolidAndOpenMeshesAreNotTrustedForFacing) {
  // Two separate cubes, the second one inside out: facing cannot be trusted for it, parity
  // can. Single-axis and robust modes both see 2 mm^3.
  TriangleMesh mixed = test::makeBox({0, 0, 0}, {1, 1, 1});
  TriangleMesh second = test::makeBox({3, 0, 0}, {4, 1, 1});
  for (glm::u32vec3 t : second.triangles) mixed.triangles.push_back({t.x + 8, t.z + 8, t.y + 8});
  mixed.positionsMm.insert(mixed.positionsMm.end(), second.positionsMm.begin(),
                           second.positionsMm.end());
  EXPECT_NEAR(voxelizeAt(mixed, 0.1).filledVolumeMm3(), 2.0, 1e-6);
  EXPECT_NEAR(voxelizeAt(mixed, 0.1, true).filledVolumeMm3(), 2.0, 1e-6);
}

TEST(Voxelizer, ParallelRunsAreIdentical) {
  const TriangleMesh torus = test::makeTorus(10.0, 4.0, 96, 48);
  const VoxelGrid a = voxelizeAt(torus, 0.3);
  const VoxelGrid b = voxelizeAt(torus, 0.3);
  ASSERT_EQ(a.dims(), b.dims());
  for (int z = 0; z < a.dims().z; ++z)
    for (int y = 0; y < a.dims().y; ++y)
      for (int x = 0; x < a.dims().x; ++x) {
        ASSERT_EQ(a.fill({x, y, z}), b.fill({x, y, z}));
        ASSERT_EQ(a.density({x, y, z}), b.density({x, y, z}));
      }
  EXPECT_TRUE(a.dirtyBricks().empty());
}

TEST(Voxelizer, BadOptionsAreInputErrors) {
  const TriangleMesh sphere = test::makeSphere(10.0, 32, 16);
  EXPECT_THROW(voxelizeAt(sphere, 0.0), InputError);
  EXPECT_THROW(voxelizeAt(sphere, -1.0), InputError);
  EXPECT_THROW(voxelizeAt(sphere, std::numeric_limits<double>::quiet_NaN()), InputError);
  EXPECT_THROW(voxelizeAt(sphere, std::numeric_limits<double>::infinity()), InputError);
  EXPECT_THROW(voxelizeAt(sphere, 1e-4), InputError);  // 2e5^3 voxels
  VoxelizeOptions options;
  options.voxelSizeMm = 1.0;
  options.raysPerAxis = 0;
  EXPECT_THROW(voxelize(sphere, options), InputError);
  options.raysPerAxis = 4;
  options.density.corticalThicknessMm = -1.0;
  EXPECT_THROW(voxelize(sphere, options), InputError);
}

class SharedBones : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(dir_ + "/fibula_L_vhm_denver.stl")) {
      GTEST_SKIP() << "shared data not found at " << dir_;
    }
  }
  std::string dir_ = OSTEON_SHARED_DATA_DIR;
};

TEST_F(SharedBones, HumerusInMetresWithinOnePercentOfItsMeshVolume) {
  const TriangleMesh humerus = readMesh(dir_ + "/humerus_R_opensim_myosuite.stl", 1000.0);
  VoxelizeStats stats;
  const VoxelGrid g = voxelizeAt(humerus, 1.0, false, &stats);
  EXPECT_LT(relativeError(g.filledVolumeMm3(), signedVolumeMm3(humerus)), 0.01);
  EXPECT_EQ(stats.raysUnresolved, 0u);
}

TEST_F(SharedBones, DensityOfEveryVoxelIsItsExactDistanceRule) {
  expectDensityFromExactDistances(readMesh(dir_ + "/fibula_L_vhm_denver.stl"), 0.45);
  expectDensityFromExactDistances(readMesh(dir_ + "/humerus_R_opensim_myosuite.stl", 1000.0), 0.9);
}

TEST_F(SharedBones, RayPacketsGiveWhatSingleRaysGive) {
  expectPacketsMatchSingleRays(readMesh(dir_ + "/fibula_L_vhm_denver.stl"), 0.7, 3);
  expectPacketsMatchSingleRays(readMesh(dir_ + "/humerus_R_opensim_myosuite.stl", 1000.0), 0.7, 3);
}

TEST_F(SharedBones, FibulaInMillimetresWithinOnePercentOfItsMeshVolume) {
  const TriangleMesh fibula = readMesh(dir_ + "/fibula_L_vhm_denver.stl");
  VoxelizeStats stats;
  const VoxelGrid g = voxelizeAt(fibula, 0.5, false, &stats);
  EXPECT_LT(relativeError(g.filledVolumeMm3(), signedVolumeMm3(fibula)), 0.01);
  EXPECT_EQ(stats.raysUnresolved, 0u);
}

}  // namespace
}  // namespace osteon::geometry
