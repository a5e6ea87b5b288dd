#include "osteon/simulation/session.h"

#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <utility>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "support/shapes.h"

namespace osteon::simulation {
namespace {

static_assert(!std::is_copy_constructible_v<Session>, "a session owns its bone: move-only");
static_assert(std::is_nothrow_move_constructible_v<Session>);

const geometry::TriangleMesh& humerus() {
  static const geometry::TriangleMesh mesh = geometry::buildHumerusModel().mesh;
  return mesh;
}

PortalPathOptions shortPath() {
  PortalPathOptions o;
  o.durationS = 1.5;
  return o;
}

// The session gives the forces of the parts wired by hand, bit for bit.
TEST(Session, RunsAsTheHandWiredPartsDo) {
  for (const int levels : {0, 2}) {
    SessionOptions options;
    options.levels = levels;
    Session session = Session::fromMesh(humerus(), options, "default");
    const DrillPath path = session.portalPath(Portal::FiveOClock, shortPath()).path;
    const RunResult a = session.run(path);

    geometry::VoxelizeOptions vo;
    vo.voxelSizeMm = 1.2;
    geometry::VoxelGrid grid = geometry::voxelize(humerus(), vo);
    auto hierarchy = geometry::DynamicProximityHierarchy::build(grid, geometry::DphBuildOptions{});
    const geometry::EmbreeScene scene(humerus());
    const geometry::FineFillSource source =
        geometry::FineFillSource::sample(grid, humerus(), scene);
    DrillingOptions drilling;
    drilling.levels = levels;
    DrillingSimulation sim(grid, hierarchy, levels > 0 ? &source : nullptr, ToolKind::Drill,
                           ToolOptions{}, drilling);
    std::vector<glm::dvec3> forces;  // the parts stepped by hand at 1 kHz
    for (std::size_t i = 0; i < a.log.size(); ++i) {
      StepInput in;
      in.tS = double(i) * 0.001;
      path.sample(in.tS, in.pose, in.drillOn);
      forces.push_back(sim.step(in).contact.forceN);
    }
    ASSERT_EQ(a.log.size(), std::size_t(std::llround(path.durationS() / 0.001)) + 1);
    for (std::size_t i = 0; i < a.log.size(); ++i) {
      ASSERT_EQ(std::memcmp(&a.log[i].forceN, &forces[i], sizeof(glm::dvec3)), 0) << "step " << i;
    }
    EXPECT_EQ(a.summary.removedVolumeMm3, sim.removedVolumeMm3());
    EXPECT_GT(a.summary.removedVolumeMm3, 0.0) << "levels " << levels;
    EXPECT_EQ(session.toolPose().tipMm, a.log.back().tipMm);
  }
}

// Moving a session moves its parts with it: the moved-to session drills on.
TEST(Session, MovesWithItsParts) {
  Session first = Session::fromMesh(humerus(), SessionOptions{}, "default");
  const DrillPath path = first.portalPath(Portal::SevenOClock, shortPath()).path;
  Session moved = std::move(first);
  const RunResult r = moved.run(path);
  EXPECT_GT(r.summary.maxForceN, 0.5);
  EXPECT_EQ(moved.surface().toTriangleMesh().triangles.size(),
            geometry::extractSurface(moved.grid(), geometry::SurfaceOptions{}).triangleCount());
}

// Sessions on one bone drill their own copies of it.
TEST(Session, SessionsOnOneBoneDrillFreshCopies) {
  const auto bone = BoneModel::fromMesh(humerus(), 1.2, "default");
  SessionOptions options;
  options.keepSurface = false;
  Session a(bone, options), b(bone, options);
  const DrillPath path = a.portalPath(Portal::FiveOClock, shortPath()).path;
  const RunResult ra = a.run(path);
  const RunResult rb = b.run(path);
  EXPECT_EQ(ra.summary.removedVolumeMm3, rb.summary.removedVolumeMm3);
  EXPECT_EQ(bone->grid().totalFill(), Session(bone, options).grid().totalFill());
  EXPECT_LT(a.grid().totalFill(), bone->grid().totalFill());
  EXPECT_THROW(a.takeSurfaceChanges(), std::logic_error);
}

// The changes a front end reads, applied to its own copy, give the session's surface.
TEST(Session, SurfaceChangesRebuildTheSurface) {
  Session session = Session::fromMesh(humerus(), SessionOptions{}, "default");
  std::vector<glm::dvec3> positions;
  std::map<std::int64_t, std::vector<glm::u32vec3>> bricks;
  const auto apply = [&](const SurfaceChanges& c) {
    positions.resize(c.slotCount, glm::dvec3(NAN));
    for (std::size_t k = 0; k < c.slots.size(); ++k) positions[c.slots[k]] = c.positionsMm[k];
    if (c.everything) bricks.clear();
    for (const SurfaceChanges::Brick& b : c.bricks) {
      if (b.triangles.empty()) {
        bricks.erase(b.key);
      } else {
        bricks[b.key] = b.triangles;
      }
    }
  };
  const auto compare = [&]() {
    // The same triangles with the same corner positions as the session's surface.
    const geometry::SurfaceMesh& s = session.surface();
    std::multiset<std::array<double, 9>> mine, theirs;
    for (const auto& [key, tris] : bricks) {
      for (const glm::u32vec3& t : tris) {
        const glm::dvec3 p[3] = {positions[t.x], positions[t.y], positions[t.z]};
        mine.insert({p[0].x, p[0].y, p[0].z, p[1].x, p[1].y, p[1].z, p[2].x, p[2].y, p[2].z});
      }
    }
    for (const glm::u32vec3& t : s.triangles) {
      const glm::dvec3 p[3] = {s.positionsMm[t.x], s.positionsMm[t.y], s.positionsMm[t.z]};
      theirs.insert({p[0].x, p[0].y, p[0].z, p[1].x, p[1].y, p[1].z, p[2].x, p[2].y, p[2].z});
    }
    return mine == theirs;
  };
  SurfaceChanges first = session.takeSurfaceChanges();
  EXPECT_TRUE(first.everything);
  apply(first);
  EXPECT_TRUE(compare());
  const DrillPath path = session.portalPath(Portal::FiveOClock, shortPath()).path;
  std::size_t changedSlots = 0, reads = 0;
  for (double t = 0.0; t <= path.durationS(); t += 0.001) {
    StepInput in;
    in.tS = t;
    path.sample(t, in.pose, in.drillOn);
    session.step(in);
    if (std::fmod(t, 0.1) < 0.001) {  // a frame every 100 steps
      const SurfaceChanges c = session.takeSurfaceChanges();
      EXPECT_FALSE(c.everything);
      changedSlots += c.slots.size();
      ++reads;
      apply(c);
    }
  }
  apply(session.takeSurfaceChanges());
  EXPECT_GT(changedSlots, 0u);
  EXPECT_LT(changedSlots, reads * session.surface().vertexCount() / 4)
      << "only what changed is listed";
  EXPECT_TRUE(compare());
  // Released, the surface is extracted from the grid (the same surface, its last bits aside);
  // changes need it kept again.
  const std::size_t vertices = session.surface().vertexCount(),
                    triangles = session.surface().triangleCount();
  session.releaseSurface();
  EXPECT_EQ(session.surface().vertexCount(), vertices);
  EXPECT_EQ(session.surface().triangleCount(), triangles);
  EXPECT_THROW(session.takeSurfaceChanges(), std::logic_error);
  session.resetSurface();
  EXPECT_TRUE(session.takeSurfaceChanges().everything);
}

// A bone from a grid (a saved grid, a label map, a CT) has no mesh: its head is fitted to the
// grid's own surface, extracted once when a portal path first asks for it.
TEST(Session, ABoneFromAGridFitsItsHeadToTheGridsSurface) {
  const auto meshBone = BoneModel::fromMesh(humerus(), 1.2, "default", 1.0, {}, false);
  const auto gridBone = BoneModel::fromGrid(meshBone->grid(), "saved.nrrd");
  EXPECT_EQ(gridBone->mesh(), nullptr);
  EXPECT_EQ(&meshBone->headMesh(), meshBone->mesh());
  // Asked from many threads at once: one extraction, one fit, the same answer for all.
  std::vector<const HumeralHead*> heads(4, nullptr);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < heads.size(); ++i) {
    threads.emplace_back([&heads, &gridBone, i] { heads[i] = &gridBone->humeralHead(); });
  }
  for (std::thread& t : threads) t.join();
  for (const HumeralHead* h : heads) EXPECT_EQ(h, heads[0]);
  EXPECT_GT(gridBone->headMesh().triangleCount(), 10000u);
  const HumeralHead& fromMesh = meshBone->humeralHead();
  const HumeralHead& fromGrid = *heads[0];
  EXPECT_LT(glm::length(fromGrid.centreMm - fromMesh.centreMm), 1.2);  // within a voxel
  EXPECT_NEAR(fromGrid.radiusMm, fromMesh.radiusMm, 1.2);
  EXPECT_GT(glm::dot(fromGrid.axis, fromMesh.axis), 0.95);
  EXPECT_GT(glm::dot(fromGrid.superior, fromMesh.superior), 0.99);

  SessionOptions options;
  options.levels = 0;
  Session session(gridBone, options);
  const PortalPlan plan = session.portalPath(Portal::FiveOClock, shortPath());
  // The axes agree within about 10 degrees: a few mm on the head's surface.
  EXPECT_LT(
      glm::length(plan.entryMm - Session(meshBone, options).portalPath(Portal::FiveOClock).entryMm),
      6.0);
  EXPECT_GT(session.run(plan.path).summary.removedVolumeMm3, 0.0);

  // No head to fit: the fit's own error, as for a mesh.
  const auto box =
      BoneModel::fromMesh(test::makeBox({0, 0, 0}, {20, 20, 60}), 1.2, "box", 1.0, {}, false);
  EXPECT_THROW(box->humeralHead(), InputError);  // the mesh: too few points
  const auto boxGrid = BoneModel::fromGrid(box->grid(), "box.nrrd");
  EXPECT_THROW(boxGrid->humeralHead(), InputError);
  EXPECT_THROW(Session(boxGrid, options).portalPath(Portal::FiveOClock), InputError);
}

// Set-up is reported stage by stage: every stage non-negative, the total at least its largest
// part, stages that did not run 0 (no timed assertions: the machine may be busy).
void expectSetupConsistent(const SetupTimings& t) {
  const double stages[] = {t.loadMs,      t.voxelizeMs,  t.densityMs,
                           t.fineFillsMs, t.hierarchyMs, t.surfaceMs};
  for (const double ms : stages) {
    EXPECT_GE(ms, 0.0);
    EXPECT_GE(t.totalMs, ms);
  }
}

TEST(Session, ReportsItsSetupTimings) {
  const Session opened = Session::open("default", 1.0, SessionOptions{});
  expectSetupConsistent(opened.setupTimings());
  EXPECT_GT(opened.setupTimings().totalMs, 0.0);
  EXPECT_GT(opened.setupTimings().fineFillsMs, 0.0);  // levels 2 samples the fine fills

  const auto bone = BoneModel::fromMesh(humerus(), 1.2, "default", 1.0, {}, false);
  expectSetupConsistent(bone->setupTimings());
  EXPECT_EQ(bone->setupTimings().loadMs, 0.0);  // given a mesh: nothing loaded
  EXPECT_EQ(bone->setupTimings().fineFillsMs, 0.0);
  EXPECT_EQ(bone->setupTimings().hierarchyMs, 0.0);  // the sessions' stages
  EXPECT_EQ(bone->setupTimings().surfaceMs, 0.0);
  SessionOptions batch;
  batch.levels = 0;
  batch.keepSurface = false;
  const Session session(bone, batch);
  const SetupTimings& t = session.setupTimings();
  expectSetupConsistent(t);
  EXPECT_EQ(t.voxelizeMs, bone->setupTimings().voxelizeMs);  // the bone's share, as it was
  EXPECT_EQ(t.surfaceMs, 0.0);                               // no surface kept
  EXPECT_GE(t.totalMs, bone->setupTimings().totalMs + t.hierarchyMs);

  const Session fromGrid = Session::fromGrid(bone->grid(), SessionOptions{}, "saved.nrrd", 12.5);
  expectSetupConsistent(fromGrid.setupTimings());
  EXPECT_EQ(fromGrid.setupTimings().loadMs, 12.5);
  EXPECT_EQ(fromGrid.setupTimings().voxelizeMs, 0.0);
  EXPECT_EQ(fromGrid.setupTimings().densityMs, 0.0);
}

TEST(Session, DisplayValuesAndBonesWithoutAMesh) {
  Session session = Session::fromMesh(humerus(), SessionOptions{}, "default");
  const glm::ivec3 centre(session.grid().gridFromWorld(session.humeralHead().centreMm));
  EXPECT_EQ(session.levelAt(centre), 0);
  EXPECT_GT(session.densityAt(centre), 0);
  EXPECT_EQ(session.levelAt({0, 0, 0}), 1);  // the padding: no bone

  geometry::VoxelGrid empty = geometry::makeGridFor(test::makeBox({0, 0, 0}, {10, 10, 10}), 1.0);
  EXPECT_THROW(Session::fromGrid(std::move(empty), SessionOptions{}, "empty.nrrd"), InputError);
  SessionOptions bad;
  bad.levels = 3;
  EXPECT_THROW(Session::fromMesh(humerus(), bad), InputError);
}

}  // namespace
}  // namespace osteon::simulation
