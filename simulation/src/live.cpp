#include "osteon/simulation/live.h"

#include <algorithm>
#include <exception>
#include <string>
#include <vector>

#include "live_impl.h"

namespace osteon::simulation {

LiveRuntime::LiveRuntime(Session& session, PoseSource& source, ForceSink* sink,
                         const RuntimeOptions& options)
    : impl_(std::make_unique<Impl>(session, source, sink, options)) {}

LiveRuntime::~LiveRuntime() {
  if (!impl_ || !impl_->started || impl_->stopped) return;
  try {
    stop();
  } catch (...) {
    // Only the session's surface reset can throw here, after the loops are joined: nothing is
    // left running, and a destructor must not throw.
  }
}

void LiveRuntime::start(double durationS) {
  Impl& m = *impl_;
  if (m.started) return;
  m.started = true;
  m.size(durationS);
  realtime::keepFreedMemory();
  const std::int64_t startNs = nowNs() + 5000000;  // 5 ms for the threads to start
  m.hapticThreadsLeft.store(m.standbyCpu >= 0 ? 2 : 1);
  m.haptic = std::thread([&m, startNs] { m.hapticLoop(startNs, 0, m.hapticCpu, false); });
  if (m.standbyCpu >= 0) {
    m.standby =
        std::thread([&m, startNs] { m.hapticLoop(startNs, kStandbyLagNs, m.standbyCpu, true); });
  }
  m.collision = std::thread([&m, startNs] { m.collisionLoop(startNs + m.periodNs / 2); });
  m.logger = std::thread([&m] { m.loggerLoop(); });
}

RuntimeResult LiveRuntime::stop() {
  Impl& m = *impl_;
  RuntimeResult result;
  if (!m.started || m.stopped) return result;
  m.stopped = true;
  m.stopFlag.store(true, std::memory_order_release);
  m.haptic.join();
  if (m.standby.joinable()) m.standby.join();
  m.collision.join();
  m.collisionDone.store(true, std::memory_order_release);
  m.logger.join();
  // What the ring holds, then the bricks it had no room for, straight into the visual grid
  // (the loops are done: nothing writes the grid now).
  try {
    m.changed.clear();
    m.surfaceReady(true);
    m.takeBacklog(true);
    while (m.bricks.pop(m.drainMsg)) {
      apply(m.visualGrid, m.drainMsg);
      m.changed.push_back(m.drainMsg.brick);
    }
    for (const std::size_t brick : m.grid->dirtyBricks()) {
      snapshot(*m.grid, brick, m.drainMsg);
      apply(m.visualGrid, m.drainMsg);
      m.changed.push_back(brick);
    }
    m.updateVisual(false);
  } catch (...) {
    m.noteVisualFault();
  }
  m.grid->clearDirty();
  if (m.session->options().keepSurface) m.session->resetSurface();

  RuntimeStats& stats = result.stats;
  stats.hapticSteps = m.hapticSteps.load();
  stats.hapticOverruns = m.hapticOverruns.load();
  stats.collisionSteps = m.collisionSteps.load();
  stats.collisionOverruns = m.collisionOverruns.load();
  const auto firstOverruns = [](const std::vector<std::int64_t>& all, std::uint64_t count) {
    return std::vector<std::int64_t>(
        all.begin(), all.begin() + std::ptrdiff_t(std::min<std::uint64_t>(count, all.size())));
  };
  stats.hapticOverrunNs = firstOverruns(m.hapticOverrunNs, stats.hapticOverruns);
  stats.collisionOverrunNs = firstOverruns(m.collisionOverrunNs, stats.collisionOverruns);
  stats.visualUpdates = m.visualUpdates;
  stats.bricksHandedOver = m.bricksHandedOver.load();
  stats.ringFull = m.ringFull.load();
  stats.logDropped = m.logDropped.load();
  stats.realtimeGranted = m.granted.load() == (m.standbyCpu >= 0 ? 3 : 2);
  stats.standbySteps = m.standbySteps.load();
  stats.hapticCpu = m.hapticCpu;
  stats.standbyCpu = m.standbyCpu;
  stats.hapticStepUs = m.hapticNs.percentiles(1e3);
  stats.collisionStepUs = m.collisionNs.percentiles(1e3);
  stats.remeshMs = m.remeshNs.percentiles(1e6);
  stats.firstStepNs = m.firstStepNs.load();
  stats.surfaceReadyNs = m.surfaceReadyNs;
  stats.surfaceBuildMs = m.surfaceBuildMs;
  result.visualFault = m.visualFault;
  result.run = m.recorder.finish(*m.sim, m.coupling != nullptr);
  RunSummary& s = result.run.summary;
  s.hapticStepUs =
      stats.collisionStepUs;  // the step the haptic target is about: collision + force + removal
  s.remeshMs = stats.remeshMs;
  s.overruns = stats.hapticOverruns + stats.collisionOverruns;
  s.steps = stats.collisionSteps;
  s.maxGapMm = m.tallies.maxGapMm;
  s.clampSteps = m.tallies.clampSteps;
  s.ringFull = stats.ringFull;
  s.logDropped = stats.logDropped;
  return result;
}

bool LiveRuntime::running() const {
  return impl_->started && !impl_->stopped;
}

bool LiveRuntime::loopsDone() const {
  return impl_->loopsFinished.load(std::memory_order_acquire) >= 2;
}

double LiveRuntime::updateSurface() {
  Impl& m = *impl_;
  // The heat conducts on the visual side, to the latest step's time (thermal.h's consumer).
  if (ThermalModel* thermal = m.session->thermal()) {
    const double tS = m.displayCore.read().tS;
    if (tS > m.diffusedS) {
      thermal->diffuse(tS - m.diffusedS);
      m.diffusedS = tS;
    }
  }
  const bool failedBefore = !m.visualFault.empty();
  const double ms = m.drainVisual();
  if (!failedBefore && !m.visualFault.empty()) throw RuntimeFault(m.visualFault);
  return ms;
}

const std::string& LiveRuntime::visualFault() const {
  return impl_->visualFault;
}

SurfaceChanges LiveRuntime::takeSurfaceChanges() {
  // Nothing yet while the first extraction runs; then everything at once.
  return impl_->updater ? impl_->updater->takeChanges() : SurfaceChanges{};
}

const geometry::SurfaceUpdater& LiveRuntime::visualSurface() const {
  impl_->surfaceReady(true);
  return *impl_->updater;
}

const geometry::VoxelGrid& LiveRuntime::visualGrid() const {
  return impl_->visualGrid;
}

const std::vector<std::size_t>& LiveRuntime::changedBricks() const {
  return impl_->lastChanged;
}

const DisplayState& LiveRuntime::display() {
  Impl& m = *impl_;
  const DisplayCore& core = m.displayCore.read();
  DisplayState& d = m.shown;
  d.tS = core.tS;
  d.pose = core.pose;
  d.commanded = core.commanded;
  d.gapMm = core.gapMm;
  d.drillOn = core.drillOn;
  d.contact = core.contact;
  d.removedFill = core.removedFill;
  d.removedVolumeMm3 = core.removedVolumeMm3;
  d.steps = core.steps;
  d.settings = core.settings;
  bool fresh = false;
  const RefinedList& refined = m.refinedList.read(&fresh);
  if (fresh) {
    d.refinedDepth = refined.depth;
    d.refinedCount = refined.count;
    std::copy(refined.voxels.begin(), refined.voxels.begin() + std::ptrdiff_t(refined.count),
              d.refined.begin());
  }
  return d;
}

void LiveRuntime::setSettings(const DrillSettings& settings) {
  impl_->rpm.store(settings.rpm, std::memory_order_relaxed);
  impl_->irrigation.store(settings.irrigation, std::memory_order_relaxed);
}

DrillSettings LiveRuntime::settings() const {
  return {impl_->rpm.load(std::memory_order_relaxed),
          impl_->irrigation.load(std::memory_order_relaxed)};
}

LiveStats LiveRuntime::stats() const {
  const Impl& m = *impl_;
  LiveStats s;
  s.hapticSteps = m.hapticSteps.load(std::memory_order_relaxed);
  s.hapticOverruns = m.hapticOverruns.load(std::memory_order_relaxed);
  s.collisionSteps = m.collisionSteps.load(std::memory_order_relaxed);
  s.collisionOverruns = m.collisionOverruns.load(std::memory_order_relaxed);
  s.bricksHandedOver = m.bricksHandedOver.load(std::memory_order_relaxed);
  s.ringFull = m.ringFull.load(std::memory_order_relaxed);
  s.collisionStepUsLast = double(m.lastStepNs.load(std::memory_order_relaxed)) * 1e-3;
  s.standbySteps = m.standbySteps.load(std::memory_order_relaxed);
  s.hapticCpu = m.hapticCpu;
  s.standbyCpu = m.standbyCpu;
  s.surfaceBuildMs = m.surfaceBuildMs;
  return s;
}

}  // namespace osteon::simulation
