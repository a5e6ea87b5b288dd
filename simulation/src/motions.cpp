#include "osteon/simulation/motions.h"

#include <cmath>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

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
                    Waypoint{o.holdS + o.pushS, end, q, o.drillOn},
                    Waypoint{o.durationS, end, q, o.drillOn}});
}

DrillPath intactPushPath(const PortalPlan& plan, const IntactPushOptions& o) {
  const glm::dvec3 in = -plan.normal;
  const ToolPose out = ToolPose::pointing(plan.entryMm - o.outsideMm * in, in);
  const ToolPose deep = ToolPose::pointing(plan.entryMm + o.depthMm * in, in);
  return DrillPath({Waypoint{0.0, out.tipMm, out.orientation, false},
                    Waypoint{o.pushS, deep.tipMm, deep.orientation, false},
                    Waypoint{o.drillOnS, deep.tipMm, deep.orientation, true},
                    Waypoint{o.durationS, deep.tipMm, deep.orientation, true}});
}

DrillPath tremorPath(const DrillPath& base, const TremorOptions& o) {
  // Phases from the engine's raw output, which the standard fixes (a distribution's is not).
  std::mt19937 engine(o.seed);
  constexpr int kAxes = 5;  // x, y, z, then the two turns
  double phase[kAxes][4];
  for (auto& axis : phase) {
    for (double& p : axis) p = 2.0 * M_PI * double(engine()) / 4294967296.0;
  }
  const auto wave = [&](int axis, double t) {
    double sum = 0.0;
    for (int k = 0; k < 4; ++k)
      sum += o.weights[k] * std::sin(2.0 * M_PI * o.frequenciesHz[k] * t + phase[axis][k]);
    return sum;
  };
  std::vector<Waypoint> points;
  const double durationS = base.durationS();
  const int n = int(std::ceil(durationS / o.sampleS));
  for (int i = 0; i <= n; ++i) {
    const double t = std::min(double(i) * o.sampleS, durationS);
    ToolPose pose;
    bool on = false;
    base.sample(t, pose, on);
    const glm::dvec3 shift = o.amplitudeMm * glm::dvec3(wave(0, t), wave(1, t), wave(2, t));
    // Two axes across the shaft: the tool's own x and y (its shaft is its -z).
    const glm::dvec3 u = pose.orientation * glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 v = pose.orientation * glm::dvec3(0.0, 1.0, 0.0);
    const double rad = o.amplitudeDeg * M_PI / 180.0;
    const glm::dquat turn =
        glm::angleAxis(rad * wave(3, t), u) * glm::angleAxis(rad * wave(4, t), v);
    points.push_back({t, pose.tipMm + shift, glm::normalize(turn * pose.orientation), on});
    if (t >= durationS) break;
  }
  return DrillPath(std::move(points));
}

}  // namespace osteon::simulation
