// The proxy coupling's geometry shared by its move (coupling_move.cpp) and its step
// (coupling.cpp): poses between two poses, and a tool part's core segment with the walk over the
// bone samples near it.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/simulation/tool.h"

namespace osteon::simulation::detail {

inline ToolPose interpolate(const ToolPose& a, const ToolPose& b, double t) {
  if (t >= 1.0) return b;
  if (t <= 0.0) return a;
  ToolPose p;
  p.tipMm = a.tipMm + t * (b.tipMm - a.tipMm);
  p.orientation = glm::normalize(glm::slerp(a.orientation, b.orientation, t));
  return p;
}

// The angle (rad) of the shortest rotation between two orientations.
inline double angleBetween(const glm::dquat& a, const glm::dquat& b) {
  const double c = std::min(1.0, std::abs(glm::dot(a, b)));
  return 2.0 * std::acos(c);
}

// A part's core segment at a pose, for distances from sample centres to it.
struct CoreSegment {
  glm::dvec3 a, b, ab;
  double invLen2 = 0.0;  // 1 / |ab|^2, or 0 for a point

  CoreSegment(const ToolPose& pose, const ToolPart& part)
      : a(pose.toWorld(part.aMm)), b(pose.toWorld(part.bMm)), ab(b - a) {
    const double len2 = glm::dot(ab, ab);
    invLen2 = len2 > 0.0 ? 1.0 / len2 : 0.0;
  }
  // Squared distance from c to the segment; toCore, when given, runs from c to its nearest point.
  double distance2(const glm::dvec3& c, glm::dvec3* toCore = nullptr) const {
    const double t = std::clamp(glm::dot(c - a, ab) * invLen2, 0.0, 1.0);
    const glm::dvec3 d = a + t * ab - c;
    if (toCore) *toCore = d;
    return glm::dot(d, d);
  }
};

// fn(sample) for every bone sample whose centre may lie within rMm of the core (the hierarchy
// walk opens only voxels that reach that far).
template <typename Fn>
void forEachSampleNearCore(geometry::RefinedVoxels& voxels, const CoreSegment& core, double rMm,
                           Fn&& fn) {
  voxels.forEachSampleNearSegment(
      core.a, core.b, rMm,
      [&](const glm::dvec3& c, double h) {
        const double far = rMm + h;
        return core.distance2(c) <= far * far;
      },
      fn);
}

}  // namespace osteon::simulation::detail
