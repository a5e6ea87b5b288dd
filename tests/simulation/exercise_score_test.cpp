// The anchor exercises' plans and four attempts built from them: the plan scores full marks, 30
// degrees off axis fails on angle, 10 mm too deep breaches the far cortex, 5 mm off the entry
// fails on entry, each for that reason.
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "osteon/simulation/exercise.h"
#include "osteon/simulation/score.h"

namespace osteon::simulation {
namespace {

struct Trial {
  TrialScore score;
  ExercisePlan plan;
};

// One attempt on a fresh session of the exercise's bone: `change` turns the plan's hole into
// the attempt's (entry, axis, depth).
// `withdrawMm`: the path then goes on that far back out along the axis, the drill off.
template <typename Change>
Trial attempt(const std::string& name, Change change, double withdrawMm = 0.0) {
  const Exercise ex = loadExercise(name);
  Session session(BoneModel::open(ex.bone).bone, exerciseSessionOptions(ex));
  Trial t;
  t.plan = planExercise(ex, session);
  glm::dvec3 entry = t.plan.entryMm, axis = t.plan.axis;
  double depthMm = t.plan.depthMm;
  change(t.plan, entry, axis, depthMm);
  DrillPath path = holePath(entry, axis, t.plan.normal, depthMm,
                            session.simulation().tool().parts[0].outerRadiusMm);
  if (withdrawMm > 0.0) {
    std::vector<Waypoint> points = path.points();
    Waypoint out = points.back();
    out.tS += withdrawMm / 10.0;
    out.tipMm -= withdrawMm * axis;
    points.push_back(out);
    path = DrillPath(points);
  }
  TrialRecorder recorder;
  session.run(
      path, recordingOptions(recorder, session.simulation().tool().maxForceN, session.coupling()));
  t.score = scoreSession(ex, t.plan, session, recorder.samples());
  return t;
}

const Criterion& criterion(const TrialScore& s, const std::string& name) {
  for (const Criterion& c : s.criteria)
    if (c.name == name) return c;
  throw std::runtime_error("no criterion " + name);
}

void expectPassedExcept(const TrialScore& s, std::initializer_list<const char*> failing) {
  for (const Criterion& c : s.criteria) {
    bool expectedToFail = false;
    for (const char* f : failing) expectedToFail = expectedToFail || c.name == f;
    EXPECT_EQ(c.passed, !expectedToFail)
        << c.name << " = " << c.value << " " << c.unit << " (limit " << c.limit << ")";
  }
}

void noChange(const ExercisePlan&, glm::dvec3&, glm::dvec3&, double&) {}

class AnchorExercise : public ::testing::TestWithParam<const char*> {};

TEST_P(AnchorExercise, ThePlanPathScoresFullMarks) {
  const Trial t = attempt(GetParam(), noChange);
  EXPECT_TRUE(t.score.passed);
  EXPECT_DOUBLE_EQ(t.score.score, 100.0);
  expectPassedExcept(t.score, {});
  EXPECT_LT(t.score.entryErrorMm, 1.0);
  EXPECT_LT(t.score.axisAngleErrorDeg, 3.0);
  EXPECT_LT(std::abs(t.score.depthVsPlanMm), 1.0);
  EXPECT_EQ(t.score.noGoMm3, 0.0);
  // A hole of the plan's size was cut: pi r^2 depth, within the voxels' rounding.
  const double holeMm3 = M_PI * t.plan.radiusMm * t.plan.radiusMm * t.plan.depthMm;
  EXPECT_GT(t.score.removedMm3, 0.6 * holeMm3);
}

TEST_P(AnchorExercise, ThePlanPathWithdrawnFurtherStillScoresFullMarks) {
  // The tip's travel once out of the hole is not the hole: its axis and depth stay the plan's.
  const Trial t = attempt(GetParam(), noChange, 30.0);
  EXPECT_TRUE(t.score.passed);
  EXPECT_DOUBLE_EQ(t.score.score, 100.0);
  expectPassedExcept(t.score, {});
  EXPECT_LT(t.score.axisAngleErrorDeg, 3.0);
  EXPECT_LT(std::abs(t.score.depthVsPlanMm), 1.0);
  EXPECT_GT(t.score.pathLengthMm, 2.0 * t.plan.depthMm + 30.0);
}

TEST_P(AnchorExercise, ThirtyDegreesOffAxisFailsOnAngle) {
  // Turned 30 degrees towards the surface normal (more upright), about the entry.
  const Trial t =
      attempt(GetParam(), [](const ExercisePlan& p, glm::dvec3&, glm::dvec3& axis, double&) {
        const glm::dvec3 about = glm::normalize(glm::cross(p.axis, -p.normal));
        axis = glm::angleAxis(30.0 * M_PI / 180.0, about) * p.axis;
        EXPECT_NEAR(std::acos(glm::dot(axis, p.axis)) * 180.0 / M_PI, 30.0, 1e-9);
      });
  EXPECT_FALSE(t.score.passed);
  EXPECT_NEAR(criterion(t.score, "angle").value, 30.0, 3.0);
  // Cutting off the planned cylinder is what an off-axis hole is.
  expectPassedExcept(t.score, {"angle", "overcut"});
}

TEST_P(AnchorExercise, TenMillimetresTooDeepBreachesTheFarCortex) {
  const Trial t = attempt(GetParam(), [](const ExercisePlan&, glm::dvec3&, glm::dvec3&,
                                         double& depthMm) { depthMm += 10.0; });
  // The axis leaves the bone within reach of a hole 10 mm deeper than planned.
  ASSERT_TRUE(t.plan.farExitMm.has_value());
  EXPECT_LT(glm::length(*t.plan.farExitMm - t.plan.entryMm),
            t.plan.depthMm + 10.0 + t.plan.radiusMm + 2.0);
  EXPECT_FALSE(t.score.passed);
  EXPECT_NEAR(t.score.depthVsPlanMm, 10.0, 1.0);
  double farMm3 = 0.0;
  for (const NoGoBreach& b : t.score.noGo) {
    if (b.zone == "far_cortex") farMm3 = b.volumeMm3;
    if (b.zone == "articular_cap") {
      EXPECT_EQ(b.volumeMm3, 0.0);
    }
  }
  EXPECT_GT(farMm3, 0.5);
  expectPassedExcept(t.score, {"depth", "no_go", "overcut"});
}

TEST_P(AnchorExercise, FiveMillimetresOffTheEntryFailsOnEntry) {
  // Along the surface, across the plane of the tilt (so the hole keeps its depth in the head).
  const Trial t =
      attempt(GetParam(), [](const ExercisePlan& p, glm::dvec3& entry, glm::dvec3&, double&) {
        entry += 5.0 * glm::normalize(glm::cross(p.normal, p.axis));
      });
  EXPECT_FALSE(t.score.passed);
  EXPECT_NEAR(criterion(t.score, "entry").value, 5.0, 1.0);
  expectPassedExcept(t.score, {"entry", "overcut"});
}

INSTANTIATE_TEST_SUITE_P(BuiltIn, AnchorExercise, ::testing::Values("anchor-5", "anchor-7"),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                           return std::string(p.param).substr(7) + "_oclock";
                         });

}  // namespace
}  // namespace osteon::simulation
