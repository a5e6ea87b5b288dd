// The humeral head is found or refused: the built-in head passes the checks, a rotated humerus
// is found at the end --up names (and refused at the other), a long shaft is refused with a
// line naming it and suggesting --up or an explicit entry point.
#include <filesystem>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/simulation/exercise.h"
#include "osteon/simulation/session.h"
#include "support/shapes.h"

namespace osteon::simulation {
namespace {

// z up becomes y up: (x, y, z) -> (x, z, -y).
glm::dvec3 zToY(const glm::dvec3& p) {
  return {p.x, p.z, -p.y};
}

geometry::TriangleMesh rotatedHumerus() {
  geometry::TriangleMesh mesh = geometry::buildHumerusModel().mesh;
  for (glm::dvec3& p : mesh.positionsMm) p = zToY(p);
  return mesh;
}

std::string refusal(const BoneModel& bone) {
  try {
    bone.humeralHead();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(HeadCheck, TheBuiltInHeadPasses) {
  const geometry::TriangleMesh mesh = geometry::buildHumerusModel().mesh;
  const HumeralHead head = fitHumeralHead(mesh);
  EXPECT_NO_THROW(checkHumeralHead(head, "default"));
  EXPECT_GT(head.radiusMm, kMinHeadRadiusMm);
  EXPECT_LT(head.radiusMm, kMaxHeadRadiusMm);
  // Given up = z, the same head.
  const HumeralHead up = fitHumeralHead(mesh, true, HeadEnd::TightestSphere, glm::dvec3(0, 0, 1));
  EXPECT_LT(glm::length(up.centreMm - head.centreMm), 0.5);
}

TEST(HeadCheck, UpFindsTheHeadOfAHumerusWhoseLongAxisIsY) {
  const geometry::TriangleMesh original = geometry::buildHumerusModel().mesh;
  const HumeralHead expected = fitHumeralHead(original);
  const auto bone =
      BoneModel::fromMesh(rotatedHumerus(), 1.2, "rotated.stl", 1.0, {}, true, glm::dvec3(0, 1, 0));
  const HumeralHead& head = bone->humeralHead();
  EXPECT_LT(glm::length(head.centreMm - zToY(expected.centreMm)), 0.5);
  EXPECT_NEAR(head.radiusMm, expected.radiusMm, 0.2);
  // The plan enters the same point of the bone, turned with it.
  const Exercise ex = loadExercise("anchor-5");
  Session rotated(bone, exerciseSessionOptions(ex));
  Session upright(BoneModel::open(ex.bone).bone, exerciseSessionOptions(ex));
  const ExercisePlan a = planExercise(ex, rotated), b = planExercise(ex, upright);
  EXPECT_LT(glm::length(a.entryMm - zToY(b.entryMm)), 0.5);
  EXPECT_GT(glm::dot(a.axis, zToY(b.axis)), 0.999);
}

TEST(HeadCheck, TheWrongUpIsRefusedNamingTheFile) {
  const auto bone = BoneModel::fromMesh(rotatedHumerus(), 1.2, "rotated.stl", 1.0, {}, true,
                                        glm::dvec3(0, -1, 0));  // the cut end of the shaft
  const std::string why = refusal(*bone);
  EXPECT_EQ(why.rfind("rotated.stl: ", 0), 0u) << why;
  EXPECT_NE(why.find("the up axis (up x"), std::string::npos) << why;
  EXPECT_EQ(why.find('\n'), std::string::npos) << why;
}

TEST(HeadCheck, TheSharedHumerusWhoseLongAxisIsYIsFoundAtTheEndUpNames) {
  const std::string file = std::string(OSTEON_SHARED_DATA_DIR) + "/humerus_R_opensim_myosuite.stl";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "shared data not found: " << file;
  const geometry::TriangleMesh mesh = geometry::readMesh(file, 1000.0);  // metres
  const HumeralHead found = fitHumeralHead(mesh);
  const HumeralHead up = fitHumeralHead(mesh, true, HeadEnd::TightestSphere, glm::dvec3(0, 1, 0));
  EXPECT_NO_THROW(checkHumeralHead(up, file));
  EXPECT_LT(glm::length(up.centreMm - found.centreMm), 1.0);
  EXPECT_GT(up.superior.y, 0.999);
  // The other end is the elbow: no humeral head there.
  const auto elbow = BoneModel::fromMesh(mesh, 1.2, file, 1000.0, {}, false, glm::dvec3(0, -1, 0));
  const std::string why = refusal(*elbow);
  EXPECT_EQ(why.rfind(file + ": ", 0), 0u) << why;
  EXPECT_NE(why.find("the up axis (up x"), std::string::npos) << why;
}

TEST(HeadCheck, ALongShaftIsNoHumerus) {
  geometry::TriangleMesh shaft = test::makeSphere(1.0, 48, 96);
  for (glm::dvec3& p : shaft.positionsMm) p *= glm::dvec3(6.0, 6.0, 60.0);
  const auto bone = BoneModel::fromMesh(shaft, 1.2, "shaft.stl");
  const std::string why = refusal(*bone);
  EXPECT_EQ(why.rfind("shaft.stl: ", 0), 0u) << why;
  EXPECT_NE(why.find("(up x|y|z|-x|-y|-z)"), std::string::npos) << why;
  EXPECT_NE(why.find("explicit entry point"), std::string::npos) << why;
  Session session(bone, SessionOptions{});
  EXPECT_THROW(session.portalPath(Portal::FiveOClock), InputError);
  EXPECT_THROW(planExercise(loadExercise("anchor-5"), session), InputError);
}

TEST(HeadCheck, AnExerciseWithAnExplicitEntryAndAxisNeedsNoHead) {
  const auto bone = BoneModel::fromMesh(test::makeBox({0, 0, 0}, {30, 30, 30}), 1.0, "box.stl");
  Exercise ex = loadExercise("anchor-5");
  ex.entryMm = glm::dvec3(15.0, 15.0, 31.0);
  ex.axis = glm::dvec3(0.0, 0.0, -1.0);
  ex.noGo.articularCap = false;
  Session session(bone, exerciseSessionOptions(ex));
  const ExercisePlan plan = planExercise(ex, session);
  EXPECT_NEAR(plan.entryMm.z, 30.0, 1e-9);
  EXPECT_NEAR(plan.normal.z, 1.0, 1e-9);
  ASSERT_TRUE(plan.farExitMm.has_value());
  EXPECT_NEAR(plan.farExitMm->z, 0.0, 0.7);
}

}  // namespace
}  // namespace osteon::simulation
