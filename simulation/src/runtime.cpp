#include "osteon/simulation/runtime.h"

#include "osteon/simulation/handoff.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

namespace osteon::simulation {

namespace {

using geometry::VoxelGrid;

std::int64_t nowNs() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return std::int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
}

void sleepUntilNs(std::int64_t deadline) {
  timespec t{};
  t.tv_sec = time_t(deadline / 1000000000);
  t.tv_nsec = long(deadline % 1000000000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr) == EINTR) {
  }
}

bool askRealtime(int priority) {
  sched_param p{};
  p.sched_priority = priority;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &p) == 0;
}

struct PoseMessage {
  double tS = -1.0;  // < 0: no pose yet
  ToolPose pose;
  bool drillOn = false;
};

struct BrickMessage {
  std::uint32_t brick = 0;
  std::array<geometry::Fill, VoxelGrid::kBrickVoxels> fill{};
};

void snapshot(const VoxelGrid& grid, std::size_t brick, BrickMessage& msg) {
  msg.brick = std::uint32_t(brick);
  if (const VoxelGrid::Brick* data = grid.brickData(brick)) {
    msg.fill = data->fill;
  } else {
    msg.fill.fill(grid.brickUniformFill(brick));
  }
}

// A fixed-period loop: runs work(k, tS) at each period k until `stop`; counts overruns; skips
// periods it has missed entirely rather than running them late.
template <typename Work>
void periodic(std::int64_t startNs, std::int64_t periodNs, std::uint64_t periods, std::uint64_t& steps,
              std::uint64_t& overruns, Durations& stepNs, Work&& work) {
  for (std::uint64_t k = 0; k < periods;) {
    const std::int64_t deadline = startNs + std::int64_t(k) * periodNs;
    sleepUntilNs(deadline);
    const std::int64_t begin = nowNs();
    work(k, double(k) * double(periodNs) * 1e-9);
    const std::int64_t end = nowNs();
    if (!stepNs.full()) stepNs.add(end - begin);
    ++steps;
    if (end > deadline + periodNs) {
      ++overruns;
      k = std::uint64_t((end - startNs) / periodNs) + 1;  // the next period not yet begun
    } else {
      ++k;
    }
  }
}

}  // namespace

RuntimeResult runThreaded(DrillingSimulation& sim, VoxelGrid& grid, PoseSource& source, ForceSink* sink,
                          const geometry::SurfaceOptions& surfaceOptions, const RuntimeOptions& options,
                          geometry::SurfaceMesh* finalSurface) {
  RuntimeResult result;
  RuntimeStats& stats = result.stats;
  const auto periods = std::uint64_t(std::llround(options.durationS / options.periodS)) + 1;
  const auto periodNs = std::int64_t(std::llround(options.periodS * 1e9));

  // Everything the 1 kHz loops touch is sized here.
  TripleBuffer<PoseMessage> poses;
  TripleBuffer<ContactForce> forces;
  SpscRing<BrickMessage> bricks(options.brickRingCapacity);
  // Rows go to the logging thread, which writes and summarises them: nothing per period is
  // kept unless asked for.
  SpscRing<ForceLogRow> logRows(options.logRingCapacity);
  std::vector<ForceLogRow>& log = result.run.log;
  if (options.keepLog) log.reserve(periods + 1);
  ForceMetrics metrics;
  metrics.reserveForStep(options.periodS);
  Durations hapticNs, collisionNs, remeshNs;
  hapticNs.reserve(periods + 1);
  collisionNs.reserve(periods + 1);

  // The visual thread owns a copy of the grid: the collision thread never waits for it and it
  // never reads a brick mid-write.
  grid.clearDirty();
  VoxelGrid visualGrid = grid;
  geometry::SurfaceUpdater updater(visualGrid, surfaceOptions);
  std::atomic<bool> stop{false};
  std::atomic<bool> collisionDone{false};
  std::atomic<int> granted{0};
  const std::int64_t startNs = nowNs() + 5000000;  // 5 ms for the threads to start

  std::thread haptic([&] {
    if (options.realtimePriority && askRealtime(80)) granted.fetch_add(1);
    periodic(startNs, periodNs, periods, stats.hapticSteps, stats.hapticOverruns, hapticNs,
             [&](std::uint64_t, double tS) {
               PoseMessage m;
               m.tS = tS;
               source.sample(tS, m.pose, m.drillOn);
               poses.write(m);
               if (sink) sink->apply(tS, forces.read().forceN);
             });
  });
  std::thread collision([&] {
    if (options.realtimePriority && askRealtime(79)) granted.fetch_add(1);
    BrickMessage handover;  // 1 KiB: kept off the loop's stack frame churn
    periodic(startNs + periodNs / 2, periodNs, periods, stats.collisionSteps, stats.collisionOverruns,
             collisionNs, [&](std::uint64_t, double) {
               const PoseMessage& m = poses.read();
               if (m.tS < 0.0) return;
               const StepOutput out = sim.step({m.tS, m.pose, m.drillOn});
               forces.write(out.contact);
               if (!logRows.push({m.tS, m.pose.tipMm, out.contact.forceN, out.contact.magnitudeN,
                                  out.contact.contactVoxels, sim.totals().samplesRemoved, out.contact.level})) {
                 ++stats.logDropped;
               }
               if (out.removal.removedFill == 0) return;
               // Hand the changed bricks around the cutting parts to the visual thread.
               const Tool& tool = sim.tool();
               for (int p = 0; p < tool.partCount; ++p) {
                 const ToolPart& part = tool.parts[std::size_t(p)];
                 if (!part.cuts) continue;
                 const glm::dvec3 a = m.pose.toWorld(part.aMm), b = m.pose.toWorld(part.bMm);
                 const double r = part.innerRadiusMm + grid.voxelSizeMm();
                 const glm::ivec3 lo = glm::max(grid.voxelFromWorld(glm::min(a, b) - r) / VoxelGrid::kBrickSize, glm::ivec3(0));
                 const glm::ivec3 hi = glm::min(grid.voxelFromWorld(glm::max(a, b) + r) / VoxelGrid::kBrickSize,
                                                grid.brickDims() - 1);
                 for (int z = lo.z; z <= hi.z; ++z)
                   for (int y = lo.y; y <= hi.y; ++y)
                     for (int x = lo.x; x <= hi.x; ++x) {
                       const std::size_t brick = grid.brickIndex({x, y, z});
                       if (!grid.brickDirty(brick)) continue;
                       snapshot(grid, brick, handover);
                       if (bricks.push(handover)) {
                         grid.clearBrickDirty(brick);
                         ++stats.bricksHandedOver;
                       } else {
                         ++stats.ringFull;  // stays dirty: handed over at a later step
                       }
                     }
               }
             });
  });
  std::thread visual([&] {
    std::vector<std::size_t> changed;
    changed.reserve(1024);
    BrickMessage msg;
    const auto drain = [&] {
      changed.clear();
      while (bricks.pop(msg)) {
        visualGrid.materialiseBrick(msg.brick).fill = msg.fill;
        visualGrid.markBrickDirty(msg.brick);
        changed.push_back(msg.brick);
      }
      if (changed.empty()) return false;
      std::sort(changed.begin(), changed.end());
      changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
      remeshNs.addMs(updater.update(changed).ms);
      visualGrid.clearDirty();
      ++stats.visualUpdates;
      return true;
    };
    while (!stop.load(std::memory_order_acquire)) {
      if (!drain()) std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    drain();
  });
  std::thread logger([&] {
    ForceLogRow row;
    const auto drain = [&] {
      bool any = false;
      while (logRows.pop(row)) {
        any = true;
        metrics.add(row.tS, row.magnitudeN);
        if (options.onRow) options.onRow(row);
        if (options.keepLog) log.push_back(row);
      }
      return any;
    };
    while (!collisionDone.load(std::memory_order_acquire)) {
      if (!drain()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    drain();
  });
  haptic.join();
  collision.join();
  collisionDone.store(true, std::memory_order_release);
  logger.join();
  // Bricks the ring had no room for are still dirty: hand them over now (no period to keep).
  for (const std::size_t brick : grid.dirtyBricks()) {
    BrickMessage msg;
    snapshot(grid, brick, msg);
    while (!bricks.push(msg)) std::this_thread::yield();
  }
  grid.clearDirty();
  stop.store(true, std::memory_order_release);
  visual.join();

  stats.realtimeGranted = granted.load() == 2;
  stats.hapticStepUs = hapticNs.percentiles(1e3);
  stats.collisionStepUs = collisionNs.percentiles(1e3);
  stats.remeshMs = remeshNs.percentiles(1e6);
  RunSummary& s = result.run.summary;
  s.jitterN = metrics.jitterN();
  s.maxStepChangeN = metrics.maxStepChangeN();
  s.maxForceN = metrics.maxForceN();
  s.removedVolumeMm3 = sim.removedVolumeMm3();
  s.hapticStepUs = stats.collisionStepUs;  // the step the haptic target is about: collision + force + removal
  s.remeshMs = stats.remeshMs;
  s.overruns = stats.hapticOverruns + stats.collisionOverruns;
  s.steps = stats.collisionSteps;
  s.totals = sim.totals();
  if (finalSurface) *finalSurface = updater.mesh();
  return result;
}

}  // namespace osteon::simulation
