#include "osteon/simulation/session.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

#include <glm/geometric.hpp>

#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/core/memory.h"
#include "osteon/core/option_error.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/hierarchy/fine_fill.h"
#include "osteon/geometry/io/units.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/live.h"
#include "run_recorder.h"
#include "surface_build.h"

namespace osteon::simulation {

// What drilling changes, on the heap so that moving the session moves one pointer and the
// references between the parts (simulation -> grid, hierarchy, fine fills) stay valid.
struct Session::State {
  std::shared_ptr<const BoneModel> bone;
  SessionOptions options;
  geometry::VoxelGrid grid;
  geometry::DynamicProximityHierarchy hierarchy;
  std::optional<DrillingSimulation> simulation;
  std::optional<ProxyCoupling> coupling;  // under proxy coupling
  std::unique_ptr<ThermalModel> thermal;  // under the calibrated model
  double diffusedS = 0.0;                 // the sim time the heat has been conducted to
  std::unique_ptr<geometry::SurfaceUpdater> updater;
  geometry::SurfaceMesh surface;
  bool surfaceStale = true;
  std::uint64_t steps = 0;
  SetupTimings setup;             // the bone's stages, then this session's
  SessionMemory visualMemory;     // the last threaded run's visual grid and surface
  std::uint64_t setupVoxels = 0;  // voxels with bone before drilling
  Clock::time_point start;        // this session's construction began (the bone's set-up before it)
  // From the start of set-up (the bone's, before this session's construction) to t.
  double sinceStartMs(Clock::time_point t) const {
    return bone->setupTimings().totalMs +
           std::chrono::duration<double, std::milli>(t - start).count();
  }
  // The first surface, from the bone as voxelized (this grid was a copy of it) while the first
  // steps change the grid. Last, so that it is waited for before the grids it reads go.
  SurfaceBuild surfaceBuild;
  // The built surface, once it is there (wait: until it is). Rethrows what the build threw.
  // catchUpMs: the update that caught up with those steps, when it was taken now.
  bool takeBuiltSurface(bool wait, double* catchUpMs = nullptr) {
    if (updater) return true;
    updater = surfaceBuild.take(wait);
    if (!updater) return false;
    setup.surfaceMs = surfaceBuild.ms();
    setup.surfaceReadyMs = sinceStartMs(surfaceBuild.done());
    const std::vector<std::size_t> dirty = grid.dirtyBricks();
    if (!dirty.empty()) {  // the steps taken while it was built
      const double ms = updater->update(dirty).ms;
      if (catchUpMs) *catchUpMs = ms;
    }
    grid.clearDirty();
    surfaceStale = true;
    return true;
  }
};

Session::Session(std::shared_ptr<const BoneModel> bone, const SessionOptions& options)
    : state_(std::make_unique<State>()) {
  const Clock::time_point start = Clock::now();
  if (!bone) throw std::logic_error("Session: constructed without a bone");
  DrillingOptions drilling = options.drilling;
  drilling.levels = options.levels;
  drilling.forceModel = options.forceModel;
  validateDrillingOptions(drilling);
  validateRpm(options.settings.rpm);
  if (options.forceModel == ForceModelKind::Calibrated && options.coupling != CouplingMode::Proxy) {
    throw OptionError("forceModel", "calibrated",
                      "the calibrated model needs proxy coupling (its proxy's feed renders it)");
  }
  if (options.keepSurface) geometry::validateSurfaceOptions(options.surface);
  State& s = *state_;
  s.bone = std::move(bone);
  s.options = options;
  s.options.voxelSizeMm = s.bone->grid().voxelSizeMm();
  s.grid = s.bone->grid();  // every session drills fresh bone
  s.setup = s.bone->setupTimings();
  s.start = start;
  const Clock::time_point hierarchyStart = Clock::now();
  s.hierarchy = geometry::DynamicProximityHierarchy::build(s.grid, geometry::DphBuildOptions{});
  s.setup.hierarchyMs = msSince(hierarchyStart);
  s.setupVoxels = s.hierarchy.voxelCount();
  s.simulation.emplace(s.grid, s.hierarchy, options.levels > 0 ? s.bone->fineFills() : nullptr,
                       options.tool, options.toolOptions, drilling);
  if (options.coupling == CouplingMode::Proxy) {
    CouplingOptions co = options.couplingOptions;
    co.forceModel = options.forceModel;
    co.materialGrid = &s.bone->grid();
    if (options.forceModel == ForceModelKind::Calibrated) {
      s.thermal = std::make_unique<ThermalModel>(s.bone->grid(), ThermalOptions{});
      co.thermal = s.thermal.get();
    }
    s.coupling.emplace(*s.simulation, co);
  }
  s.grid.clearDirty();
  s.setup.totalMs = s.bone->setupTimings().totalMs + msSince(start);
  // From the bone, not this grid: it runs beside the first steps, whose bricks stay dirty until
  // the first update after it is taken catches up with them.
  if (options.keepSurface) s.surfaceBuild.start(s.grid, options.surface, s.bone->grid());
}

Session::Session(Session&&) noexcept = default;
Session& Session::operator=(Session&&) noexcept = default;
Session::~Session() = default;

Session Session::fromMesh(geometry::TriangleMesh meshMm, const SessionOptions& options,
                          const std::string& name, double loadScaleToMm) {
  return Session(BoneModel::fromMesh(std::move(meshMm), options.voxelSizeMm, name, loadScaleToMm,
                                     options.voxelizing, options.levels > 0),
                 options);
}

Session Session::open(const std::string& meshArgument, double scaleToMm,
                      const SessionOptions& options) {
  return Session(BoneModel::open(meshArgument, scaleToMm, options.voxelSizeMm, options.voxelizing,
                                 options.levels > 0),
                 options);
}

Session Session::fromGrid(geometry::VoxelGrid grid, const SessionOptions& options,
                          const std::string& name, double loadMs) {
  return Session(BoneModel::fromGrid(std::move(grid), name, loadMs), options);
}

StepOutput Session::step(const StepInput& input) {
  return hapticStep(input).step;
}

HapticStep Session::hapticStep(const StepInput& input) {
  const bool follow =
      surfaceEverySteps > 0 && (state_->steps + 1) % std::uint64_t(surfaceEverySteps) == 0;
  return advance(input, coupling(), follow, nullptr, nullptr);
}

HapticStep Session::advance(const StepInput& input, ProxyCoupling* coupling, bool followSurface,
                            Durations* stepNs, Durations* surfaceNs) {
  State& s = *state_;
  const Clock::time_point start = Clock::now();
  if (s.steps == 0) s.setup.firstStepMs = s.sinceStartMs(start);
  const HapticStep h = stepHaptic(*s.simulation, coupling, input);
  if (stepNs) stepNs->add(std::chrono::nanoseconds(Clock::now() - start).count());
  // The heat conducts every 10 ms of the run's time (the threaded runtime: its visual thread).
  if (s.thermal && input.tS - s.diffusedS >= 0.01) {
    s.thermal->diffuse(input.tS - s.diffusedS);
    s.diffusedS = input.tS;
  }
  lastPose_ = h.proxy;
  lastContact_ = h.step.contact;
  lastContact_.forceN = h.forceN;
  lastContact_.magnitudeN = h.magnitudeN;
  ++s.steps;
  s.surfaceStale = true;
  // The visual work: once the first surface is there, it follows the changed bricks.
  double catchUpMs = -1.0;
  if (followSurface && s.takeBuiltSurface(false, &catchUpMs)) {
    if (surfaceNs && catchUpMs >= 0.0) surfaceNs->addMs(catchUpMs);
    const std::vector<std::size_t> dirty = s.grid.dirtyBricks();
    if (!dirty.empty()) {
      const double ms = s.updater->update(dirty).ms;
      if (surfaceNs) surfaceNs->addMs(ms);
      s.grid.clearDirty();
    }
  }
  return h;
}

RunResult Session::run(const DrillPath& path, const DeterministicOptions& options) {
  ProxyCoupling* const proxy = options.coupling ? options.coupling : coupling();
  const auto steps = std::size_t(std::llround(path.durationS() / options.stepS)) + 1;
  RunRecorder recorder(options.onRow, options.keepLog, options.stepS);
  recorder.reserve(steps);
  Durations stepNs, surfaceNs;
  stepNs.reserve(steps);
  RunSummary tallies;
  for (std::size_t i = 0; i < steps; ++i) {
    StepInput input;
    input.tS = double(i) * options.stepS;
    input.settings = state_->options.settings;
    path.sample(input.tS, input.pose,
                input.drillOn);  // haptic: the device (here the path) gives the pose
    const bool follow =
        options.remeshEverySteps > 0 && i % std::size_t(options.remeshEverySteps) == 0;
    const HapticStep h = advance(input, proxy, follow, &stepNs, &surfaceNs);
    tallies.tally(h);
    recorder.add(logRowOf(input, h, simulation()));
    if (options.afterStep)
      options.afterStep(i, {input.tS, h.proxy, input.drillOn, input.settings}, h.step);
    if (interrupted()) break;  // SIGINT/SIGTERM: the caller throws Interrupted
  }
  RunResult result = recorder.finish(simulation(), proxy != nullptr);
  RunSummary& s = result.summary;
  s.hapticStepUs = stepNs.percentiles(1e3);
  s.remeshMs = surfaceNs.percentiles(1e6);
  s.steps = steps;
  s.maxGapMm = tallies.maxGapMm;
  s.clampSteps = tallies.clampSteps;
  return result;
}

RuntimeResult Session::runThreaded(PoseSource& source, ForceSink* sink,
                                   const RuntimeOptions& options) {
  State& s = *state_;
  LiveRuntime live(*this, source, sink, options);
  live.start(options.durationS);
  // The visual thread: as fast as it can, the handed-over bricks into the surface. A surface
  // that failed will not be right again: the run has failed, so the loops stop now.
  std::atomic<bool> loopsOver{false}, visualFailed{false};
  std::thread visual([&] {
    while (!loopsOver.load(std::memory_order_acquire)) {
      try {
        const double ms = live.updateSurface();
        if (options.onVisual) options.onVisual(live, false);
        if (ms == 0.0) std::this_thread::sleep_for(std::chrono::microseconds(500));
      } catch (...) {  // RuntimeFault: the error is kept in live.visualFault()
        visualFailed.store(true, std::memory_order_release);
        return;
      }
    }
  });
  // SIGINT/SIGTERM stop the loops early; the caller throws Interrupted.
  while (!live.loopsDone() && !visualFailed.load(std::memory_order_acquire) && !interrupted()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  loopsOver.store(true, std::memory_order_release);
  visual.join();
  // Drilled up to here; stop() starts the session's own surface again from the grid.
  RuntimeResult result = live.stop();
  // The first step and the visual surface's first extraction, against this session's set-up.
  const auto at = [](std::int64_t ns) {
    return Clock::time_point(
        std::chrono::duration_cast<Clock::duration>(std::chrono::nanoseconds(ns)));
  };
  if (result.stats.firstStepNs > 0 && s.setup.firstStepMs == 0.0)
    s.setup.firstStepMs = s.sinceStartMs(at(result.stats.firstStepNs));
  if (result.stats.surfaceReadyNs > 0 && s.setup.surfaceReadyMs == 0.0) {
    s.setup.surfaceMs = result.stats.surfaceBuildMs;
    s.setup.surfaceReadyMs = s.sinceStartMs(at(result.stats.surfaceReadyNs));
  }
  if (options.onVisual && result.visualFault.empty()) options.onVisual(live, true);
  if (result.visualFault.empty()) {
    s.visualMemory.visualGrid = live.visualGrid().memoryBytes();
    s.visualMemory.surface = live.visualSurface().memory();
  }
  s.surfaceStale = true;
  if (!result.visualFault.empty()) {
    std::ostringstream m;
    m.precision(3);
    m << std::fixed << result.visualFault
      << "; the haptic and collision loops were stopped cleanly after "
      << result.stats.collisionSteps << " steps (t = " << live.display().tS << " s)";
    throw RuntimeFault(m.str());
  }
  if (s.options.keepSurface) {  // only a session that keeps its surface keeps the visual thread's
                                // (a copy)
    s.surface = live.visualSurface().mesh();
    s.surfaceStale = false;
  }
  return result;
}

const geometry::SurfaceMesh& Session::surface() {
  State& s = *state_;
  s.takeBuiltSurface(true);
  if (s.surfaceStale) {
    s.surface = s.updater ? s.updater->mesh() : geometry::extractSurface(s.grid, s.options.surface);
    s.surfaceStale = false;
  }
  return s.surface;
}

void Session::resetSurface() {
  State& s = *state_;
  if (!s.options.keepSurface) {
    throw std::logic_error(s.bone->name() + ": the session keeps no surface (keepSurface is off)");
  }
  s.takeBuiltSurface(true);
  s.grid.clearDirty();
  s.updater = std::make_unique<geometry::SurfaceUpdater>(s.grid, s.options.surface);
  s.surfaceStale = true;
}

void Session::releaseSurface() {
  State& s = *state_;
  s.takeBuiltSurface(true);  // its timings are kept
  s.updater.reset();
  s.surface = geometry::SurfaceMesh{};
  s.surfaceStale = true;
  giveBackFreedMemory();
}

SurfaceChanges Session::takeSurfaceChanges() {
  State& s = *state_;
  s.takeBuiltSurface(true);
  if (!s.updater) {
    throw std::logic_error(s.bone->name() +
                           ": the session keeps no surface (keepSurface off, or released)");
  }
  return s.updater->takeChanges();
}

geometry::SurfaceMesh Session::multiResolutionSurface() const {
  const State& s = *state_;
  return geometry::extractSurface(s.grid, s.simulation->voxels(), s.options.surface);
}

int Session::levelAt(const glm::ivec3& voxel) const {
  const State& s = *state_;
  if (s.grid.fill(voxel) == 0) return 1;
  return s.simulation->voxels().isRefined(voxel) ? -s.simulation->voxels().depth() : 0;
}

geometry::Density Session::densityAt(const glm::ivec3& voxel) const {
  return state_->grid.density(voxel);
}

const BoneModel& Session::bone() const {
  return *state_->bone;
}
const geometry::VoxelGrid& Session::grid() const {
  return state_->grid;
}
const geometry::DynamicProximityHierarchy& Session::hierarchy() const {
  return state_->hierarchy;
}
DrillingSimulation& Session::simulation() {
  return *state_->simulation;
}
ThermalModel* Session::thermal() {
  return state_->thermal.get();
}

const ThermalModel* Session::thermal() const {
  return state_->thermal.get();
}

ProxyCoupling* Session::coupling() {
  return state_->coupling ? &*state_->coupling : nullptr;
}
const DrillingSimulation& Session::simulation() const {
  return *state_->simulation;
}
const SessionOptions& Session::options() const {
  return state_->options;
}
const SetupTimings& Session::setupTimings() const {
  return state_->setup;
}

SessionMemory Session::memory() {
  State& s = *state_;
  s.takeBuiltSurface(true);
  SessionMemory m = s.visualMemory;  // the threaded runtime's visual side, if it ran
  m.voxels = s.setupVoxels;
  m.boneGrid = s.bone->grid().memoryBytes();
  m.fineFills = s.bone->fineFills() ? s.bone->fineFills()->memoryBytes() : 0;
  m.grid = s.grid.memoryBytes();
  m.hierarchy = s.hierarchy.memoryBytes();
  m.refinement = s.simulation->voxels().memoryBytes();
  m.thermal = s.thermal ? s.thermal->memoryBytes() : 0;
  if (s.updater) m.surface = s.updater->memory();
  return m;
}

const HumeralHead& Session::humeralHead() const {
  return state_->bone->humeralHead();
}

PortalPlan Session::portalPath(Portal portal, const PortalPathOptions& options) const {
  const HumeralHead& head = humeralHead();  // throws for a bone without a head
  return makePortalPath(portal, head, state_->bone->headMesh(),
                        state_->simulation->tool().parts[0].outerRadiusMm, options);
}

}  // namespace osteon::simulation
