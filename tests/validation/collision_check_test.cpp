#include "osteon/validation/collision_check.h"

#include <gtest/gtest.h>

#include "osteon/geometry/io/humerus_model.h"
#include "osteon/simulation/session.h"

namespace osteon::validation {
namespace {

using namespace osteon::simulation;

CollisionCheckResult drill(int levels, bool updateSurface,
                           geometry::SurfaceMethod method = geometry::SurfaceMethod::CrackFree) {
  SessionOptions options;
  options.levels = levels;
  // Refined voxels split their fill evenly here (no fine fills): the check holds either way.
  Session session(
      BoneModel::fromMesh(geometry::buildHumerusModel().mesh, 1.2, "default", 1.0, {}, false),
      options);
  const PortalPlan plan = session.portalPath(Portal::FiveOClock);
  CollisionCheckOptions check;
  check.everySteps = 25;
  check.updateSurface = updateSurface;
  check.method = method;
  return crossCheckCollisions(session, plan.path, check);
}

// The crack-free surface, kept up to date, shields every bone sample the rays test, at every
// checked step, and the rays are many (the check is not vacuous).
TEST(CollisionCheck, TheCrackFreeSurfaceNeverMissesAContact) {
  for (const int levels : {0, 2}) {
    const CollisionCheckResult r = drill(levels, true);
    EXPECT_EQ(r.checked, 281u);
    EXPECT_GT(r.contacts, 200u) << "levels " << levels;
    EXPECT_GT(r.raysCast, 5000u) << "levels " << levels;
    EXPECT_LT(r.skippedSteps, r.contacts / 2) << "levels " << levels;
    EXPECT_EQ(r.missedSamples, 0u) << "levels " << levels;
    EXPECT_EQ(r.misses, 0u) << "levels " << levels;
    EXPECT_EQ(r.falseContacts, 0u) << "levels " << levels;
  }
}

// The seed's naive surface, on the same path, lets rays through its cracks to bone the voxels
// put in the tool's shell: the same rays (they follow the voxels alone), misses where the
// crack-free surface has none.
TEST(CollisionCheck, TheNaiveSurfaceMissesWhereTheCrackFreeOneDoesNot) {
  const CollisionCheckResult crackFree = drill(0, true);
  const CollisionCheckResult naive = drill(0, true, geometry::SurfaceMethod::Naive);
  EXPECT_EQ(naive.raysCast, crackFree.raysCast);
  EXPECT_EQ(crackFree.misses, 0u);
  EXPECT_GT(naive.misses, 0u);
  EXPECT_GT(naive.missedSamples, naive.misses);
}

// The check can fail: a surface that stops following the drill (the bone it shows is gone)
// leaves the tool deep inside it, its rays to the bone around the hole crossing nothing.
TEST(CollisionCheck, AStaleSurfaceShowsMisses) {
  const CollisionCheckResult r = drill(0, false);
  EXPECT_GT(r.misses, 50u);
  EXPECT_GT(r.worstMissMm, 1.0);
}

}  // namespace
}  // namespace osteon::validation
