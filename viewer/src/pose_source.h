// The viewer's device: where the haptic loop finds the tool. Without a haptic device the mouse
// sets a target pose (render thread, through a triple buffer) and the tool follows it at a
// bounded speed, so a jump of the cursor drills a straight channel rather than teleporting the
// tool into the bone; with --path the pose follows the path in wall-clock time from the start
// (the tool stays at the path's end afterwards). Either way every sample can be recorded.
#pragma once

#include "osteon/core/handoff.h"
#include "osteon/simulation/path.h"
#include "osteon/simulation/runtime.h"
#include "recorder.h"

namespace osteon::viewer {

class ViewerPoseSource : public simulation::PoseSource {
 public:
  static constexpr double kMaxSpeedMmPerS = 100.0;
  static constexpr double kMaxTurnRadPerS = 6.0;

  // path: null for the mouse; otherwise it must outlive this source.
  ViewerPoseSource(const simulation::ToolPose& initial, const simulation::DrillPath* path);

  // ---- render thread ----
  // The pose the tool moves towards, and the drill's state (the mouse; ignored with a path).
  void setTarget(const simulation::ToolPose& pose, bool drillOn);
  bool followsPath() const { return path_ != nullptr; }
  PathRecorder& recorder() { return recorder_; }
  // ---- one other thread (the runtime's logging thread) ----
  // The latest sample's pose and drill state, as the haptic loop took them.
  void latestSample(simulation::ToolPose& pose, bool& drillOn) noexcept {
    const Target& t = sampled_.read();
    pose = t.pose;
    drillOn = t.drillOn;
  }

  // ---- haptic thread ----
  void sample(double tS, simulation::ToolPose& pose, bool& drillOn) noexcept override;

 private:
  struct Target {
    simulation::ToolPose pose;
    bool drillOn = false;
  };
  const simulation::DrillPath* path_;
  core::TripleBuffer<Target> target_;
  core::TripleBuffer<Target> sampled_;  // haptic thread -> logging thread
  // The haptic thread's own state.
  simulation::ToolPose current_;
  double lastTS_ = -1.0;
  PathRecorder recorder_;
};

// Moves `from` towards `to` by at most maxMm of travel and maxRad of turn (plain math, for the
// mouse source and its tests).
simulation::ToolPose stepTowards(const simulation::ToolPose& from, const simulation::ToolPose& to,
                                 double maxMm, double maxRad);

}  // namespace osteon::viewer
