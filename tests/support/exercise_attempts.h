// Attempts at an exercise as path CSVs (what `osteon score` and `osteon-viewer --path` read):
// its plan changed in entry, axis or depth, and the three bad attempts the exercise tests hold
// to failing for their own reasons.
#pragma once

#include <functional>
#include <string>

#include <glm/vec3.hpp>

#include "osteon/simulation/exercise.h"

namespace osteon::test {

// Turns the plan's hole into the attempt's: its entry, axis and depth.
using AttemptChange = std::function<void(const simulation::ExercisePlan& plan, glm::dvec3& entryMm,
                                         glm::dvec3& axis, double& depthMm)>;

// The path CSV of `exercise`'s plan (a built-in's name or a file) changed by `change`.
std::string attemptCsv(const std::string& exercise, const AttemptChange& change);

// 30 degrees off the planned axis, turned towards the surface normal about the entry.
void thirtyDegreesOffAxis(const simulation::ExercisePlan& plan, glm::dvec3& entryMm,
                          glm::dvec3& axis, double& depthMm);
// The entry 5 mm off along the surface, across the plane of the tilt.
void entryFiveMillimetresOff(const simulation::ExercisePlan& plan, glm::dvec3& entryMm,
                             glm::dvec3& axis, double& depthMm);
// 10 mm deeper than planned.
void tenMillimetresTooDeep(const simulation::ExercisePlan& plan, glm::dvec3& entryMm,
                           glm::dvec3& axis, double& depthMm);

}  // namespace osteon::test
