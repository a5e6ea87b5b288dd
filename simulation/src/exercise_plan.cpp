// An exercise resolved against the opened bone: entry, axis, head and the ideal path
// (exercise.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "osteon/core/error.h"
#include "osteon/core/number_text.h"
#include "osteon/simulation/exercise.h"
#include "osteon/simulation/score.h"

namespace osteon::simulation {

namespace {

constexpr double kPlanSpeedMmPerS = 2.5;  // about the seed's portal paths' speed
constexpr double kPlanHoldS = 1.0;        // at full depth, so a proxy that lags gets there
constexpr double kPlanRetractS = 2.0;
constexpr double kNormalRadiusMm = 4.0;  // the surface the plan's normal is averaged over

glm::dvec3 closestOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                             const glm::dvec3& c) {
  // Ericson, Real-Time Collision Detection, 5.1.5.
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// The surface point nearest `p` and the outward normal of its triangle (outward: towards less
// bone in the grid).
void projectOntoSurface(const geometry::TriangleMesh& mesh, const geometry::VoxelGrid& grid,
                        const glm::dvec3& p, glm::dvec3& onMm, glm::dvec3& normal) {
  double best = std::numeric_limits<double>::infinity();
  geometry::forEachTriangle(mesh,
                            [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
                              const glm::dvec3 n = glm::cross(b - a, c - a);
                              if (!(glm::length(n) > 0.0)) return;
                              const glm::dvec3 q = closestOnTriangle(p, a, b, c);
                              const double d = glm::length(q - p);
                              if (d < best) {
                                best = d;
                                onMm = q;
                                normal = glm::normalize(n);
                              }
                            });
  if (!std::isfinite(best)) throw InputError("entry_mm: the bone has no surface to enter");
  const double stepMm = 1.5 * grid.voxelSizeMm();
  if (fillFractionAt(grid, onMm + stepMm * normal) > fillFractionAt(grid, onMm - stepMm * normal))
    normal = -normal;
}

// The surface's outward normal around the entry: the area-weighted normals of the triangles
// within radiusMm, so one steep facet of a low-poly mesh does not turn the plan along the
// surface. `facet` (outward) orients them.
glm::dvec3 surfaceNormalAround(const geometry::TriangleMesh& mesh, const glm::dvec3& entryMm,
                               const glm::dvec3& facet, double radiusMm) {
  glm::dvec3 sum(0.0);
  geometry::forEachTriangle(
      mesh, [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
        if (glm::length((a + b + c) / 3.0 - entryMm) > radiusMm) return;
        const glm::dvec3 n = glm::cross(b - a, c - a);  // twice the area, along the normal
        sum += glm::dot(n, facet) >= 0.0 ? n : -n;
      });
  return glm::length(sum) > 0.0 ? glm::normalize(sum) : facet;
}

// Where the line from the entry along the axis leaves the bone (the grid's half-fill surface).
std::optional<glm::dvec3> farExit(const geometry::VoxelGrid& grid, const glm::dvec3& entryMm,
                                  const glm::dvec3& axis) {
  const double stepMm = 0.25 * grid.voxelSizeMm();
  const glm::dvec3 extent = glm::dvec3(grid.dims()) * grid.voxelSizeMm();
  const double maxMm = glm::length(extent);
  bool inside = false;
  for (double s = 0.0; s < maxMm; s += stepMm) {
    const bool now = fillFractionAt(grid, entryMm + s * axis) >= 0.5;
    if (inside && !now) return entryMm + s * axis;
    inside = inside || now;
  }
  return std::nullopt;
}

}  // namespace

DrillPath holePath(const glm::dvec3& entryMm, const glm::dvec3& axis, const glm::dvec3& normal,
                   double depthMm, double toolOuterRadiusMm) {
  // Back from the entry until the cushion clears the tangent plane by 1 mm.
  const double cosIn = std::max(0.2, -glm::dot(axis, normal));
  const double approachMm = (toolOuterRadiusMm + 1.0) / cosIn;
  const glm::dvec3 start = entryMm - approachMm * axis;
  const glm::dvec3 end = entryMm + depthMm * axis;
  const glm::dquat q = ToolPose::pointing(start, axis).orientation;
  const double drillS = (approachMm + depthMm) / kPlanSpeedMmPerS;
  return DrillPath({Waypoint{0.0, start, q, true}, Waypoint{drillS, end, q, true},
                    Waypoint{drillS + kPlanHoldS, end, q, true},
                    Waypoint{drillS + kPlanHoldS + kPlanRetractS, start, q, false}});
}

ExercisePlan planExercise(const Exercise& ex, const Session& session) {
  const BoneModel& bone = session.bone();
  const geometry::TriangleMesh& mesh = bone.headMesh();
  ExercisePlan plan;
  // The head is needed for the portal's entry, for the default axis (the tendon's pull) and for
  // the cartilage cap; else it is shown when there is one.
  const bool needHead = !ex.entryMm || !ex.axis || ex.noGo.articularCap;
  if (needHead) {
    plan.head = session.humeralHead();  // throws, suggesting --up or an explicit entry point
  } else {
    try {
      plan.head = session.humeralHead();
    } catch (const InputError&) {
    }
  }
  const double outerRadiusMm = session.simulation().tool().parts[0].outerRadiusMm;
  if (ex.entryMm) {
    projectOntoSurface(mesh, bone.grid(), *ex.entryMm, plan.entryMm, plan.normal);
  } else {
    PortalPathOptions portal;
    portal.entryAngleDeg = ex.axisAngleDeg;
    portal.depthMm = ex.depthMm;
    const PortalPlan p = makePortalPath(ex.portal, *plan.head, mesh, outerRadiusMm, portal);
    plan.entryMm = p.entryMm;
    plan.normal = p.normal;
  }
  plan.normal = surfaceNormalAround(mesh, plan.entryMm, plan.normal, kNormalRadiusMm);
  if (ex.axis) {
    plan.axis = glm::normalize(*ex.axis);
    if (!(glm::dot(plan.axis, plan.normal) < -1e-6)) {
      throw InputError((ex.file.empty() ? ex.name : ex.file) +
                       ": axis.direction: points out of the bone at the entry");
    }
  } else {
    // The deadman rule (exercise.h): from the inward normal towards the tendon's pull, taken
    // as the head axis in the tangent plane (makePortalPath tilts the same way).
    glm::dvec3 pull = plan.head->axis - glm::dot(plan.head->axis, plan.normal) * plan.normal;
    if (glm::length(pull) < 1e-6) pull = glm::cross(plan.normal, glm::dvec3(0.0, 0.0, 1.0));
    if (glm::length(pull) < 1e-6) pull = glm::cross(plan.normal, glm::dvec3(1.0, 0.0, 0.0));
    const double a = ex.axisAngleDeg * M_PI / 180.0;
    plan.axis = glm::normalize(-std::cos(a) * plan.normal + std::sin(a) * glm::normalize(pull));
  }
  plan.depthMm = ex.depthMm;
  plan.radiusMm = 0.5 * ex.diameterMm;
  plan.endMm = plan.entryMm + plan.depthMm * plan.axis;
  plan.farExitMm = farExit(bone.grid(), plan.entryMm, plan.axis);
  // A plan whose hole leaves the bone is no plan: its own path would breach the far side.
  const double reachMm = plan.depthMm + plan.radiusMm + ex.noGo.farCortexMm;
  if (plan.farExitMm && glm::length(*plan.farExitMm - plan.entryMm) < reachMm) {
    throw InputError(bone.name() + ": the planned hole leaves the bone " +
                     numberText(glm::length(*plan.farExitMm - plan.entryMm)) +
                     " mm from the entry (it goes " + numberText(plan.depthMm) +
                     " mm deep): give an explicit entry point (entry_mm) or axis (axis.direction)");
  }
  plan.path = holePath(plan.entryMm, plan.axis, plan.normal, plan.depthMm, outerRadiusMm);
  return plan;
}

}  // namespace osteon::simulation
