// LiveRuntime's state and its threads' loops (live.cpp: starting, stopping and what the render
// thread reads). Included by live.cpp only.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "live_messages.h"
#include "osteon/core/error.h"
#include "osteon/core/handoff.h"
#include "osteon/simulation/live.h"
#include "realtime_thread.h"
#include "run_recorder.h"
#include "surface_build.h"

namespace osteon::simulation {

namespace live_detail {

using geometry::VoxelGrid;
using namespace messages;
using realtime::nowNs;
using realtime::prefaultStack;
using realtime::sleepUntilNs;

// The haptic standby wakes this long after each period's start: late enough that the first
// thread has nearly always run the period, early enough to run it well inside it.
constexpr std::int64_t kStandbyLagNs = 250000;
// How many steps apart the refined voxels are published (a 48 KiB copy).
constexpr std::uint64_t kRefinedEverySteps = 16;
// Changed bricks in flight to the visual thread, and force log rows on their way to the logging
// thread; past these the ring is full and the loss is counted (ringFull, logDropped).
constexpr std::size_t kBrickRingCapacity = 4096;
constexpr std::size_t kLogRingCapacity = 65536;
// Step timings kept for percentiles: ten minutes at 1 kHz, then only the latest is known.
constexpr std::uint64_t kMaxTimedPeriods = 600000;

// The exception being handled, as one line.
std::string currentErrorLine() {
  std::string text = "an exception that is not a std::exception";
  try {
    throw;
  } catch (const std::exception& e) {
    text = e.what();
  } catch (...) {
  }
  return oneLine(text);
}

}  // namespace live_detail

using namespace live_detail;

struct LiveRuntime::Impl {
  Session* session;
  DrillingSimulation* sim;
  ProxyCoupling* coupling;  // null: direct
  RunSummary tallies;       // the collision thread's (gap, clamps), read after it is joined
  VoxelGrid* grid;
  PoseSource* source;
  ForceSink* sink;
  RuntimeOptions options;
  std::uint64_t periods = std::numeric_limits<std::uint64_t>::max();  // per loop; max: until stop()
  std::int64_t periodNs;

  core::TripleBuffer<PoseMessage> poses;
  // The drill's settings (setSettings(), from any thread): the haptic loop's base each period.
  std::atomic<double> rpm{1000.0};
  std::atomic<bool> irrigation{false};
  double diffusedS = 0.0;  // the visual thread's: the time the heat has been conducted to
  core::TripleBuffer<ContactForce> forces;
  core::TripleBuffer<DisplayCore> displayCore;
  core::TripleBuffer<RefinedList> refinedList;
  core::SpscRing<BrickMessage, kBrickRingCapacity> bricks;
  core::SpscRing<ForceLogRow, kLogRingCapacity> logRows;
  RunRecorder recorder;  // the logging thread's
  Durations hapticNs, collisionNs, remeshNs;

  VoxelGrid visualGrid;
  std::unique_ptr<geometry::SurfaceUpdater> updater;  // null until its first extraction is taken
  // The first extraction, of visualGrid on a thread of its own while the loops run; until it is
  // taken, handed-over bricks wait in `backlog` (visualGrid must not change under it).
  SurfaceBuild surfaceBuild;
  // Handed-over bricks not yet in visualGrid, oldest first. Each update takes as many distinct
  // bricks as fit its time budget (the surface lags a frame or two, but whole: no update waits
  // on a burst such as a jump of the tool or the first extraction's backlog).
  std::deque<BrickMessage> backlog;
  static constexpr double kRemeshBudgetMs = 8.0;
  double msPerBrick = 0.05;  // what an update has cost per brick, learnt as they run
  double surfaceBuildMs = 0.0;
  std::int64_t surfaceReadyNs = 0;
  std::atomic<std::int64_t> firstStepNs{0};
  std::vector<std::size_t> changed;
  std::vector<std::size_t> lastChanged;  // the last drain's bricks (LiveRuntime::changedBricks)
  BrickMessage drainMsg;
  DisplayState shown;
  std::uint64_t visualUpdates = 0;
  std::string visualFault;  // set once; the visual surface is left as it was from then on

  std::atomic<bool> stopFlag{false};
  std::atomic<bool> collisionDone{false};
  std::atomic<int> loopsFinished{0};
  std::atomic<int> granted{0};
  std::atomic<std::uint64_t> hapticSteps{0}, hapticOverruns{0}, collisionSteps{0},
      collisionOverruns{0};
  // The haptic loop's claim word: 2 x the next period to run, + 1 while one of its threads
  // runs it. The release store after each period orders one thread's work before the other's.
  std::atomic<std::uint64_t> hapticClaim{0};
  std::atomic<std::uint64_t> standbySteps{0};
  std::atomic<int> hapticThreadsLeft{0};
  int hapticCpu = -1, standbyCpu = -1;  // standbyCpu < 0: no standby thread
  std::vector<std::int64_t> hapticOverrunNs, collisionOverrunNs;  // sized and written up front
  std::atomic<std::uint64_t> bricksHandedOver{0}, ringFull{0}, logDropped{0};
  std::atomic<std::int64_t> lastStepNs{0};
  std::thread haptic, standby, collision, logger;
  bool started = false, stopped = false;

  Impl(Session& se, PoseSource& src, ForceSink* snk, const RuntimeOptions& o)
      : session(&se),
        sim(&se.simulation()),
        coupling(o.coupling ? o.coupling : se.coupling()),
        grid(&se.simulation().grid()),
        source(&src),
        sink(snk),
        options(o),
        periodNs(std::int64_t(std::llround(o.periodS * 1e9))),
        recorder(o.onRow, o.keepLog, o.periodS) {
    rpm.store(se.options().settings.rpm);
    irrigation.store(se.options().settings.irrigation);
    hapticOverrunNs.assign(RuntimeStats::kOverrunInstantsKept, 0);
    collisionOverrunNs.assign(RuntimeStats::kOverrunInstantsKept, 0);
    changed.reserve(1024);
    const std::vector<int> cpus = realtime::allowedCpus();
    if (options.hapticStandby && cpus.size() >= 2) {
      hapticCpu = cpus.back();
      standbyCpu = cpus.front();
    }
    // The visual side owns a copy of the grid: the collision thread never waits for it and it
    // never reads a brick mid-write.
    grid->clearDirty();
    visualGrid = *grid;
    surfaceBuild.start(visualGrid, se.options().surface, visualGrid);
  }

  // The visual surface, once its first extraction is there (wait: until it is); then the
  // bricks handed over meanwhile go into visualGrid and `changed`. Rethrows what the build threw.
  bool surfaceReady(bool wait) {
    if (updater) return true;
    updater = surfaceBuild.take(wait);
    if (!updater) return false;
    surfaceBuildMs = surfaceBuild.ms();
    surfaceReadyNs =
        std::chrono::duration_cast<std::chrono::nanoseconds>(surfaceBuild.done().time_since_epoch())
            .count();
    return true;
  }

  // Applies the oldest handed-over bricks to visualGrid: all of them, or as many distinct
  // bricks as the budget allows (a brick already taken this time costs nothing more).
  void takeBacklog(bool all) {
    const auto budget = std::size_t(std::clamp(kRemeshBudgetMs / msPerBrick, 4.0, 1024.0));
    while (!backlog.empty()) {
      const std::size_t brick = backlog.front().brick;
      const bool seen = std::find(changed.begin(), changed.end(), brick) != changed.end();
      if (!all && !seen && changed.size() >= budget) break;
      apply(visualGrid, backlog.front());
      if (!seen) changed.push_back(brick);
      backlog.pop_front();
    }
  }

  // Everything the loops touch is sized here, before they start (periods known).
  void size(double durationS) {
    if (std::isfinite(durationS))
      periods = std::uint64_t(std::llround(durationS / options.periodS)) + 1;
    const std::uint64_t timed = std::min<std::uint64_t>(periods, kMaxTimedPeriods) + 1;
    recorder.reserve(timed);
    hapticNs.reserve(timed);
    collisionNs.reserve(timed);
  }

  // A fixed-period loop: runs work(k, tS) at each period k until `periods` or stop; counts
  // overruns; skips periods it has missed entirely rather than running them late.
  template <typename Work>
  void periodic(std::int64_t startNs, std::atomic<std::uint64_t>& steps,
                std::atomic<std::uint64_t>& overruns, std::vector<std::int64_t>& overrunNs,
                Durations& stepNs, Work&& work) {
    prefaultStack();
    for (std::uint64_t k = 0; k < periods && !stopFlag.load(std::memory_order_relaxed);) {
      const std::int64_t deadline = startNs + std::int64_t(k) * periodNs;
      sleepUntilNs(deadline);
      const std::int64_t begin = nowNs();
      work(double(k) * double(periodNs) * 1e-9);
      const std::int64_t end = nowNs();
      if (!stepNs.full()) stepNs.add(end - begin);
      steps.fetch_add(1, std::memory_order_relaxed);
      if (end > deadline + periodNs) {
        const std::uint64_t n =
            overruns.fetch_add(1, std::memory_order_relaxed);  // this loop's own count
        if (n < overrunNs.size()) overrunNs[n] = end;
        k = std::uint64_t((end - startNs) / periodNs) + 1;  // the next period not yet begun
      } else {
        ++k;
      }
    }
    loopsFinished.fetch_add(1, std::memory_order_release);
  }

  // One of the haptic loop's two threads (the second only with a standby). Each wakes at its
  // own lag after every period's start, and the first to find the period unclaimed runs it: a
  // CPU the hypervisor or kernel holds for a millisecond stalls one thread, not the loop
  // (docs/performance.md, "Threaded runtime"). Overruns and skipped periods as in periodic().
  void hapticLoop(std::int64_t startNs, std::int64_t lagNs, int cpu, bool isStandby) {
    realtime::pinTo(cpu);
    if (options.realtimePriority && realtime::askRealtime(80)) granted.fetch_add(1);
    prefaultStack();
    for (std::uint64_t k = 0; !stopFlag.load(std::memory_order_relaxed);) {
      sleepUntilNs(startNs + std::int64_t(k) * periodNs + lagNs);
      std::uint64_t claim = hapticClaim.load(std::memory_order_acquire);
      const std::uint64_t next = claim >> 1;
      if (next >= periods) break;
      if (next > k) {  // the other thread ran (or skipped) this one: wake for the next
        k = next;
        continue;
      }
      if ((claim & 1) != 0) {  // the other thread is inside period `next`'s work
        // Wake for the period after this one: while the other thread is stalled inside its
        // work, this one sleeps a period at a time instead of spinning on a past deadline.
        k = std::max(k, next) + 1;
        continue;
      }
      if (!hapticClaim.compare_exchange_strong(claim, claim | 1, std::memory_order_acq_rel))
        continue;
      const std::int64_t deadline = startNs + std::int64_t(next) * periodNs;
      const std::int64_t begin = nowNs();
      hapticWork(double(next) * double(periodNs) * 1e-9);
      const std::int64_t end = nowNs();
      if (!hapticNs.full()) hapticNs.add(end - begin);
      hapticSteps.fetch_add(1, std::memory_order_relaxed);
      if (isStandby) standbySteps.fetch_add(1, std::memory_order_relaxed);
      k = next + 1;
      if (end > deadline + periodNs) {
        const std::uint64_t n = hapticOverruns.fetch_add(1, std::memory_order_relaxed);
        if (n < hapticOverrunNs.size()) hapticOverrunNs[n] = end;
        k = std::uint64_t((end - startNs) / periodNs) + 1;  // the next period not yet begun
      }
      hapticClaim.store(2 * k, std::memory_order_release);
    }
    if (hapticThreadsLeft.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      loopsFinished.fetch_add(1, std::memory_order_release);
    }
  }

  void hapticWork(double tS) {
    PoseMessage m;
    m.tS = tS;
    source->sample(tS, m.pose, m.drillOn);
    m.settings = {rpm.load(std::memory_order_relaxed), irrigation.load(std::memory_order_relaxed)};
    source->settings(m.settings);
    poses.write(m);
    if (sink) sink->apply(tS, forces.read().forceN);
  }

  void collisionLoop(std::int64_t startNs) {
    if (options.realtimePriority && realtime::askRealtime(79)) granted.fetch_add(1);
    BrickMessage handover;
    RefinedList refined;
    periodic(
        startNs, collisionSteps, collisionOverruns, collisionOverrunNs, collisionNs, [&](double) {
          const std::int64_t begin = nowNs();
          const PoseMessage& m = poses.read();
          if (m.tS < 0.0) return;
          if (firstStepNs.load(std::memory_order_relaxed) == 0)
            firstStepNs.store(begin, std::memory_order_relaxed);
          const HapticStep h = stepHaptic(*sim, coupling, {m.tS, m.pose, m.drillOn, m.settings});
          const StepOutput& out = h.step;
          // The haptic thread sends the coupling's force (direct: the contact force).
          ContactForce sent = out.contact;
          sent.forceN = h.forceN;
          sent.magnitudeN = h.magnitudeN;
          forces.write(sent);
          tallies.tally(h);
          const DrillingTotals& totals = sim->totals();
          if (!logRows.push(logRowOf({m.tS, m.pose, m.drillOn, m.settings}, h, *sim))) {
            logDropped.fetch_add(1, std::memory_order_relaxed);
          }
          displayCore.write({m.tS, h.proxy, h.commanded, h.gapMm, m.drillOn, sent,
                             totals.removedFill, sim->removedVolumeMm3(), totals.steps,
                             m.settings});
          if (totals.steps % kRefinedEverySteps == 0) {
            const geometry::RefinedVoxels& voxels = sim->voxels();
            refined.depth = voxels.depth();
            refined.count = std::min(voxels.refinedCount(), refined.voxels.size());
            for (std::size_t i = 0; i < refined.count; ++i)
              refined.voxels[i] = voxels.refinedVoxelAt(i);
            refinedList.write(refined);
          }
          if (out.removal.removedFill > 0) {
            PoseMessage at = m;  // the bone changed where the step ran (the cut pose)
            at.pose = h.stepPose;
            handOver(at, handover);
          }
          lastStepNs.store(nowNs() - begin, std::memory_order_relaxed);
        });
  }

  // The changed bricks around the cutting parts, to the visual side.
  void handOver(const PoseMessage& m, BrickMessage& handover) {
    const Tool& tool = sim->tool();
    for (int p = 0; p < tool.partCount; ++p) {
      const ToolPart& part = tool.parts[std::size_t(p)];
      if (!part.cuts) continue;
      const glm::dvec3 a = m.pose.toWorld(part.aMm), b = m.pose.toWorld(part.bMm);
      const double r = part.innerRadiusMm + grid->voxelSizeMm();
      const glm::ivec3 lo =
          glm::max(grid->voxelFromWorld(glm::min(a, b) - r) / VoxelGrid::kBrickSize, glm::ivec3(0));
      const glm::ivec3 hi = glm::min(
          grid->voxelFromWorld(glm::max(a, b) + r) / VoxelGrid::kBrickSize, grid->brickDims() - 1);
      for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int x = lo.x; x <= hi.x; ++x) {
            const std::size_t brick = grid->brickIndex({x, y, z});
            if (!grid->brickDirty(brick)) continue;
            snapshot(*grid, brick, handover);
            if (bricks.push(handover)) {
              grid->clearBrickDirty(brick);
              bricksHandedOver.fetch_add(1, std::memory_order_relaxed);
            } else {
              ringFull.fetch_add(
                  1, std::memory_order_relaxed);  // stays dirty: handed over at a later step
            }
          }
    }
  }

  void loggerLoop() {
    ForceLogRow row;
    const auto drain = [&] {
      bool any = false;
      while (logRows.pop(row)) {
        any = true;
        recorder.add(row);
      }
      return any;
    };
    while (!collisionDone.load(std::memory_order_acquire)) {
      if (!drain()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    drain();
  }

  // The visual side: handed-over bricks into its grid, the surface updated. Never throws: a
  // failure is kept in visualFault.
  double drainVisual() {
    try {
      changed.clear();
      lastChanged.clear();
      while (bricks.pop(drainMsg)) backlog.push_back(drainMsg);
      if (!surfaceReady(false)) return 0.0;
      takeBacklog(false);
      return updateVisual();
    } catch (...) {
      noteVisualFault();
      return 0.0;
    }
  }

  // timed: a remesh while drilling (stop()'s last flush, after the loops, is not one).
  double updateVisual(bool timed = true) {
    if (changed.empty()) return 0.0;
    if (!visualFault.empty()) {  // a surface that failed once is not trusted with more changes
      visualGrid.clearDirty();
      changed.clear();
      return 0.0;
    }
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
    if (options.beforeSurfaceUpdate) options.beforeSurfaceUpdate();
    const double ms = updater->update(changed).ms;
    if (timed) remeshNs.addMs(ms);
    if (changed.size() >= 4)
      msPerBrick = 0.8 * msPerBrick + 0.2 * std::max(ms, 1e-3) / double(changed.size());
    visualGrid.clearDirty();
    ++visualUpdates;
    lastChanged.swap(changed);
    changed.clear();
    return ms;
  }

  // Called in a catch block of the visual side.
  void noteVisualFault() {
    if (visualFault.empty())
      visualFault = "the visual surface update failed: " + currentErrorLine();
    changed.clear();
  }
};

}  // namespace osteon::simulation
