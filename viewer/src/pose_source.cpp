#include "pose_source.h"

#include <algorithm>
#include <cmath>

namespace osteon::viewer {

simulation::ToolPose stepTowards(const simulation::ToolPose& from, const simulation::ToolPose& to,
                                 double maxMm, double maxRad) {
  simulation::ToolPose out = to;
  const glm::dvec3 d = to.tipMm - from.tipMm;
  const double len = glm::length(d);
  if (len > maxMm) out.tipMm = from.tipMm + d * (maxMm / len);
  glm::dquat q = to.orientation;
  const double dot = glm::dot(from.orientation, q);
  if (dot < 0.0) q = -q;
  const double angle = 2.0 * std::acos(std::min(1.0, std::abs(dot)));
  if (angle > maxRad && angle > 0.0)
    out.orientation = glm::slerp(from.orientation, q, maxRad / angle);
  return out;
}

ViewerPoseSource::ViewerPoseSource(const simulation::ToolPose& initial,
                                   const simulation::DrillPath* path)
    : path_(path), current_(initial) {
  target_.write(Target{initial, false});
}

void ViewerPoseSource::setTarget(const simulation::ToolPose& pose, bool drillOn) {
  target_.write(Target{pose, drillOn});
}

void ViewerPoseSource::sample(double tS, simulation::ToolPose& pose, bool& drillOn) noexcept {
  if (path_) {
    path_->sample(tS, pose, drillOn);
  } else {
    const Target& t = target_.read();
    const double dt = lastTS_ < 0.0 ? 0.0 : std::max(tS - lastTS_, 0.0);
    current_ = stepTowards(current_, t.pose, kMaxSpeedMmPerS * dt, kMaxTurnRadPerS * dt);
    pose = current_;
    drillOn = t.drillOn;
  }
  lastTS_ = tS;
  recorder_.add(tS, pose, drillOn);
  sampled_.write(Target{pose, drillOn});
}

}  // namespace osteon::viewer
