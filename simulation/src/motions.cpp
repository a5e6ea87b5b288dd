#include "osteon/simulation/motions.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

namespace osteon::simulation {

DrillPath lateralSweepPath(const PortalPlan& plan, const LateralSweepOptions& o) {
  const std::vector<Waypoint>& planned = plan.path.points();
  const glm::dquat q = planned.front().orientation;
  const glm::dvec3 start = planned.front().tipMm;
  // Across the plane of travel and the normal: along the surface, square to the travel.
  const glm::dvec3 side = glm::normalize(glm::cross(plan.normal, plan.direction));
  const auto at = [&](double depthMm) { return plan.entryMm - depthMm * plan.normal; };
  std::vector<Waypoint> points;
  const int n = int(std::ceil(o.durationS / o.sampleS));
  for (int i = 0; i <= n; ++i) {
    const double t = std::min(double(i) * o.sampleS, o.durationS);
    glm::dvec3 p;
    if (t <= o.reachS) {
      const double s = t / o.reachS;
      p = start + s * (at(o.startDepthMm) - start);
    } else {
      const double depth = o.startDepthMm + o.sinkMmPerS * (t - o.reachS);
      p = at(depth) + o.amplitudeMm * std::sin(2.0 * M_PI * o.frequencyHz * (t - o.reachS)) * side;
    }
    points.push_back({t, p, q, true});
    if (t >= o.durationS) break;
  }
  return DrillPath(std::move(points));
}

DrillPath fastPushPath(const PortalPlan& plan, const FastPushOptions& o) {
  const std::vector<Waypoint>& planned = plan.path.points();
  const glm::dquat q = planned.front().orientation;
  const glm::dvec3 start = planned.front().tipMm;
  const glm::dvec3 end = plan.entryMm + o.depthMm * plan.direction;
  return DrillPath({Waypoint{0.0, start, q, o.drillOn}, Waypoint{o.holdS, start, q, o.drillOn},
                    Waypoint{o.holdS + o.pushS, end, q, o.drillOn}, Waypoint{o.durationS, end, q, o.drillOn}});
}

}  // namespace osteon::simulation
