// The threaded runtime (seed 4: "three separate threads for collision detection, and visual and
// haptic rendering"):
//   haptic     1 kHz: device pose in, the latest force out; on two threads pinned to two
//              CPUs, the second standing by for a period the first has not begun in time
//   collision  1 kHz: the latest pose -> a drilling step (refine, force, removal); the force
//              and every changed brick handed on
//   visual     as fast as it can: changed bricks into its own copy of the grid, the surface
//              updated incrementally
//   logging    every few ms: the collision thread's force log rows to RuntimeOptions::onRow and
//              the summary's metrics, so the log is streamed, not kept
// The 1 kHz loops never allocate, lock or throw: hand-offs are triple buffers and bounded
// rings (core/handoff.h), timings go to arrays sized before the start. Periods are
// kept with clock_nanosleep on CLOCK_MONOTONIC to absolute deadlines; a period whose work ends
// after its deadline is an overrun, and missed periods are skipped, not run late.
// Faults stay off the 1 kHz loops: a visual side that stalls only delays the surface, one whose
// surface update throws stops the run cleanly (RuntimeFault), and the force log is written by
// the logging thread, whose failures (a full disk) the writer keeps to itself (force_log.h).
// LiveRuntime (live.h) is the runtime; Session::runThreaded runs one for durationS with a
// visual thread of its own.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/simulation/drilling.h"
#include "osteon/simulation/path.h"
#include "osteon/simulation/runner.h"

namespace osteon::simulation {

class LiveRuntime;

// The device side: where the tool is, and where the force goes. Called from the haptic loop
// only, on either of its two threads but never on both at once; each call sees all that the
// previous one did. Must not block, allocate or throw.
class PoseSource {
 public:
  virtual ~PoseSource() = default;
  virtual void sample(double tS, ToolPose& pose, bool& drillOn) noexcept = 0;
  // After sample(): the rpm and irrigation the source sets (a board's knob, a recording's
  // columns); `settings` holds the session's own, which a source without controls leaves.
  virtual void settings(DrillSettings& settings) noexcept { (void)settings; }
};

class ForceSink {
 public:
  virtual ~ForceSink() = default;
  virtual void apply(double tS, const glm::dvec3& forceN) noexcept = 0;
};

// A scripted device: the pose along a drill path, in wall-clock time from the start.
class PathPoseSource : public PoseSource {
 public:
  explicit PathPoseSource(const DrillPath& path) : path_(&path) {}
  void sample(double tS, ToolPose& pose, bool& drillOn) noexcept override {
    path_->sample(tS, pose, drillOn);
  }

 private:
  const DrillPath* path_;
};

struct RuntimeOptions {
  double durationS = 7.0;  // Session::runThreaded's run (a LiveRuntime's is start()'s)
  double periodS = 0.001;
  bool realtimePriority = true;  // ask for SCHED_FIFO (granted only with the privilege)
  // With two or more CPUs, the haptic loop runs on two threads pinned to different CPUs: the
  // standby runs a period the first has not begun 250 us into it.
  bool hapticStandby = true;
  // Rows as they come, on the logging thread (not a 1 kHz loop); must not throw.
  std::function<void(const ForceLogRow& row)> onRow;
  bool keepLog = true;  // also collect every row in RuntimeResult::run.log
  // The proxy coupling the collision thread steps through (coupling.h); null: direct (a
  // LiveRuntime on a session then takes the session's own coupling, if it has one).
  ProxyCoupling* coupling = nullptr;
  // Called on the visual side before each surface update, never in a 1 kHz loop: the seam
  // through which tests make the update throw (the CLI's OSTEON_INJECT_FAULT=surface-update
  // sets it, for tests of the whole program).
  std::function<void()> beforeSurfaceUpdate;
  // Called on Session::runThreaded's visual thread after each surface update (last: once more
  // after the loops stopped, with what was left), never in a 1 kHz loop: front ends that serve
  // the session elsewhere (the OpenIGTLink server) read display(), visualGrid() and
  // changedBricks() there. Must not throw.
  std::function<void(LiveRuntime& live, bool last)> onVisual;
};

struct RuntimeStats {
  std::uint64_t hapticSteps = 0, collisionSteps = 0;
  std::uint64_t hapticOverruns = 0, collisionOverruns = 0;
  std::uint64_t visualUpdates = 0;
  std::uint64_t bricksHandedOver = 0;
  std::uint64_t ringFull = 0;    // changed bricks the visual thread could not be given
  std::uint64_t logDropped = 0;  // force log rows the logging thread's ring had no room for
  Percentiles hapticStepUs, collisionStepUs, remeshMs;
  bool realtimeGranted = false;
  std::uint64_t standbySteps = 0;       // haptic periods its standby thread ran
  int hapticCpu = -1, standbyCpu = -1;  // where the haptic threads are pinned (-1: no standby)
  // When the first overruns happened (CLOCK_MONOTONIC ns at the late period's end; at most
  // kOverrunInstantsKept each): to line them up with what else the machine did then.
  static constexpr std::size_t kOverrunInstantsKept = 4096;
  std::vector<std::int64_t> hapticOverrunNs, collisionOverrunNs;
  // CLOCK_MONOTONIC ns of the first collision step and of the visual surface's first
  // extraction being there (it runs beside the first steps), and how long that took; 0: never.
  std::int64_t firstStepNs = 0, surfaceReadyNs = 0;
  double surfaceBuildMs = 0.0;
};

struct RuntimeResult {
  RunResult run;  // force log (collision thread) and the summary of runner.h
  RuntimeStats stats;
  std::string visualFault;  // the visual surface update's error in one line; empty: none
};

// The runtime's own work failed (the visual surface update threw), not the input: the loops
// were stopped cleanly first. what() is one line.
class RuntimeFault : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace osteon::simulation
