// The threaded runtime kept running for an interactive front end (the viewer): the haptic and
// collision loops run at 1 kHz in their own threads until stop(), as in `drill --threaded`
// (runtime.h), and the visual work is the caller's, done on its own thread (a render loop)
// through updateSurface(). Everything the render thread reads comes through hand-offs (a
// triple buffer of display state, a ring of changed bricks into its own grid copy): it never
// touches what the collision thread writes, and the 1 kHz loops never wait for it: a render
// thread that stalls (a hung driver, a debugger) only delays the surface, which catches up at
// its next update.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/simulation/runtime.h"
#include "osteon/simulation/session.h"

namespace osteon::simulation {

// What a frame shows of the simulation, published by the collision thread.
struct DisplayState {
  static constexpr std::size_t kMaxRefined = 4096;
  double tS = -1.0;    // < 0: no step yet
  ToolPose pose;       // the tool: the proxy under proxy coupling
  ToolPose commanded;  // the device's pose (the tool's under direct coupling)
  double gapMm = 0.0;  // between the two tips
  bool drillOn = false;
  ContactForce contact;           // its forceN: what the device is sent (before the safety layer)
  std::uint64_t removedFill = 0;  // grid fill units removed so far
  double removedVolumeMm3 = 0.0;
  std::uint64_t steps = 0;
  DrillSettings settings;  // the step's rpm and irrigation (a device's controls included)
  // The voxels refined now and to which depth (refreshed every few steps).
  int refinedDepth = 0;
  std::size_t refinedCount = 0;
  std::array<glm::ivec3, kMaxRefined> refined;
};

// Counters of the loops so far, readable from any thread.
struct LiveStats {
  std::uint64_t hapticSteps = 0, hapticOverruns = 0;
  std::uint64_t collisionSteps = 0, collisionOverruns = 0;
  std::uint64_t bricksHandedOver = 0, ringFull = 0;
  double collisionStepUsLast = 0.0;  // the latest step's duration
  std::uint64_t standbySteps = 0;    // haptic periods run by its standby thread (runtime.h)
  int hapticCpu = -1, standbyCpu = -1;
  // The visual surface's first extraction, beside the first steps: how long it took (0 while
  // it runs). Read on the visual side (the thread that calls updateSurface).
  double surfaceBuildMs = 0.0;
};

// The one threaded runtime: Session::runThreaded is this with a visual thread of its own.
class LiveRuntime {
 public:
  // The session must outlive the runtime and must not be stepped by anyone else while it runs.
  // options.durationS is not read: start() takes the duration.
  LiveRuntime(Session& session, PoseSource& source, ForceSink* sink,
              const RuntimeOptions& options = {});
  ~LiveRuntime();  // stops
  LiveRuntime(const LiveRuntime&) = delete;
  LiveRuntime& operator=(const LiveRuntime&) = delete;

  // Starts the loops; they run until stop(), or for durationS (whole periods, the last one at
  // t = durationS) and then end by themselves (loopsDone()).
  void start(double durationS = std::numeric_limits<double>::infinity());
  // Joins the loops; hands over what is left; the session's own surface starts again from its
  // grid. Returns the run as Session::runThreaded does (force log metrics, step percentiles, and a
  // visual fault in visualFault rather than thrown).
  RuntimeResult stop();
  bool running() const;

  // ---- the render thread ----
  // Applies the bricks handed over since the last call to the visual grid and updates the
  // visual surface. Returns the update's milliseconds (0 when nothing changed).
  // If the update throws, the 1 kHz loops go on untouched and the call throws RuntimeFault
  // (runtime.h), once, naming the error; from then on the visual surface stays as it was and
  // later calls only keep the hand-over drained (returning 0). RuntimeOptions::
  // beforeSurfaceUpdate is called before each update (tests make it throw).
  double updateSurface();
  // The visual surface's changes since the last call (everything on the first).
  SurfaceChanges takeSurfaceChanges();
  const geometry::SurfaceUpdater& visualSurface() const;
  // The visual thread's copy of the grid (fill and density), as of the last updateSurface().
  const geometry::VoxelGrid& visualGrid() const;
  // The bricks the last updateSurface() (or stop()) applied to visualGrid(), sorted, unique.
  const std::vector<std::size_t>& changedBricks() const;
  // The latest display state (a reference valid until the next call).
  const DisplayState& display();
  // The surface update's error in one line, empty while there is none.
  const std::string& visualFault() const;

  // ---- any thread ----
  LiveStats stats() const;
  // The drill's rpm and irrigation from the next haptic period on (a device's controls act on
  // them); starts with the session's. Lock-free.
  void setSettings(const DrillSettings& settings);
  DrillSettings settings() const;
  // True once the loops have run for the duration start() was given (never before stop()
  // without one).
  bool loopsDone() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace osteon::simulation
