// One opened bone and its drilling: the session, the path or the mouse, the pose source and the
// live runtime (haptic and collision loops at 1 kHz). Loading does all the slow work
// (voxelization, the hierarchy, the first surface) and can run off the render thread; a load
// that fails throws InputError before anything is shown.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "options.h"
#include "osteon/simulation/device_input.h"
#include "osteon/simulation/exercise.h"
#include "osteon/simulation/live.h"
#include "osteon/simulation/score.h"
#include "osteon/simulation/session.h"
#include "pose_source.h"

namespace osteon::viewer {

// Where the drilling happens: the entry point on the bone and the surface's outward normal.
struct WorkSite {
  glm::dvec3 pointMm{0.0};
  glm::dvec3 outward{0.0, 0.0, 1.0};
  bool entry = false;  // a portal's planned entry (not just where a path or the tool starts)
  std::optional<simulation::HumeralHead> head;  // the head the portal was fitted to
};

class Scene {
 public:
  // Throws InputError "<file or value>: <reason>" for bad input.
  static std::unique_ptr<Scene> load(const LoadRequest& request);
  ~Scene();  // stops the loops
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  void start() { live_->start(); }
  // Joins the loops (the recorder can then be read); idempotent.
  simulation::RuntimeResult stop();

  const LoadRequest& request() const { return request_; }
  simulation::Session& session() { return *session_; }
  simulation::LiveRuntime& live() { return *live_; }
  ViewerPoseSource& poseSource() { return *source_; }
  // The attached device's adapter (null: the mouse or a path).
  simulation::DeviceInput* deviceInput() { return deviceInput_.get(); }
  const simulation::Tool& tool() const { return session_->simulation().tool(); }
  // The scripted path (null: the mouse).
  const simulation::DrillPath* path() const { return path_ ? &*path_ : nullptr; }
  double pathDurationS() const { return path_ ? path_->durationS() : 0.0; }
  // Where the tool starts (the path's start, or aimed at the humeral head, or above the bone).
  const simulation::ToolPose& initialPose() const { return initialPose_; }
  // The arthroscope's device (--scope-device): its newest pose in the session's frame, polled
  // from the render thread at the loops' time tS. False without one or before its first sample.
  bool pollScope(double tS, glm::dvec3& tipMm, glm::dvec3& axis, std::int64_t& knob);
  // The exercise and its plan against this bone (null without one).
  const simulation::Exercise* exercise() const { return exercise_ ? &*exercise_ : nullptr; }
  const simulation::ExercisePlan* plan() const { return plan_ ? &*plan_ : nullptr; }
  // Stops the loops and scores the trial so far (an exercise only); the same metrics as
  // `osteon score`. The loops do not start again: Backspace reloads the bone for another try.
  simulation::TrialScore scoreTrial();
  // The portal's entry (or where the tool starts): what the arthroscope looks at.
  const WorkSite& work() const { return work_; }
  // The grid's extent, what the camera frames.
  glm::dvec3 boundsMin() const { return boundsMin_; }
  glm::dvec3 boundsMax() const { return boundsMax_; }
  double periodS() const { return options_.periodS; }
  double loadMs() const { return loadMs_; }
  std::optional<simulation::RuntimeResult>& result() { return result_; }

 private:
  Scene() = default;
  // The trial's samples: a buffer allocated now, filled by the runtime's rows.
  void recordTrial();
  LoadRequest request_;
  simulation::RuntimeOptions options_;
  std::unique_ptr<simulation::Session> session_;
  std::optional<simulation::DrillPath> path_;
  std::unique_ptr<ViewerPoseSource> source_;
  // With --device: the device, and its adapter through the safety layer (pose in, force out).
  std::unique_ptr<devices::Device> device_;
  std::unique_ptr<simulation::DeviceInput> deviceInput_;
  std::unique_ptr<devices::Device> scopeDevice_;
  simulation::DeviceFrame scopeFrame_;
  devices::DeviceSample scopeSample_;
  std::unique_ptr<simulation::LiveRuntime> live_;
  simulation::ToolPose initialPose_;
  WorkSite work_;
  std::optional<simulation::Exercise> exercise_;
  std::optional<simulation::ExercisePlan> plan_;
  // What the haptic loop did, for the score: filled on the runtime's logging thread.
  std::unique_ptr<simulation::TrialRecorder> trial_;
  glm::dvec3 boundsMin_{0.0}, boundsMax_{0.0};
  double loadMs_ = 0.0;
  std::optional<simulation::RuntimeResult> result_;
};

}  // namespace osteon::viewer
