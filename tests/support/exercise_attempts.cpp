#include "support/exercise_attempts.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "osteon/simulation/path.h"
#include "osteon/simulation/session.h"

namespace osteon::test {

std::string attemptCsv(const std::string& exercise, const AttemptChange& change) {
  using namespace simulation;
  const Exercise ex = loadExercise(exercise);
  Session session(BoneModel::open(ex.bone).bone, exerciseSessionOptions(ex));
  const ExercisePlan plan = planExercise(ex, session);
  glm::dvec3 entry = plan.entryMm, axis = plan.axis;
  double depthMm = plan.depthMm;
  change(plan, entry, axis, depthMm);
  return drillPathCsv(holePath(entry, axis, plan.normal, depthMm,
                               session.simulation().tool().parts[0].outerRadiusMm));
}

void thirtyDegreesOffAxis(const simulation::ExercisePlan& plan, glm::dvec3&, glm::dvec3& axis,
                          double&) {
  const glm::dvec3 about = glm::normalize(glm::cross(plan.axis, -plan.normal));
  axis = glm::angleAxis(30.0 * M_PI / 180.0, about) * plan.axis;
}

void entryFiveMillimetresOff(const simulation::ExercisePlan& plan, glm::dvec3& entryMm, glm::dvec3&,
                             double&) {
  entryMm += 5.0 * glm::normalize(glm::cross(plan.normal, plan.axis));
}

void tenMillimetresTooDeep(const simulation::ExercisePlan&, glm::dvec3&, glm::dvec3&,
                           double& depthMm) {
  depthMm += 10.0;
}

}  // namespace osteon::test
