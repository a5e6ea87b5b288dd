// The live runtime a viewer drives: the 1 kHz loops in their threads, the visual work on the
// caller's thread through hand-offs only.
#include "osteon/simulation/live.h"

#include <atomic>
#include <chrono>
#include <pthread.h>
#include <sched.h>
#include <thread>
#include <time.h>

#include <gtest/gtest.h>

#include "osteon/geometry/io/humerus_model.h"
#include "support/humerus_session.h"

namespace osteon::simulation {
namespace {

TEST(LiveRuntime, DrillsWhileTheCallerRendersAndEndsEqualToTheGrid) {
  SessionOptions options;
  Session session = test::humerusSession(options);
  const DrillPath path = test::portalFivePath(session, 1.2);
  PathPoseSource source(path);
  RuntimeOptions ro;
  ro.realtimePriority = false;
  ro.keepLog = false;
  LiveRuntime live(session, source, nullptr, ro);
  live.start();
  EXPECT_TRUE(live.running());
  // The surface is extracted beside the first steps: nothing until it is there, then the whole
  // of it once, then only changes.
  std::size_t frames = 0, changedFrames = 0, refinedSeen = 0, everything = 0;
  double maxForce = 0.0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(1600);
  while (std::chrono::steady_clock::now() < until) {  // a render loop at about 60 Hz
    live.updateSurface();
    const SurfaceChanges c = live.takeSurfaceChanges();
    if (c.everything) {
      EXPECT_EQ(everything, 0u);
      EXPECT_EQ(changedFrames, 0u);
      ++everything;
      continue;
    }
    if (everything == 0) {
      EXPECT_EQ(c.slotCount, 0u);
    }
    changedFrames += c.bricks.empty() ? 0u : 1u;
    const DisplayState& d = live.display();
    maxForce = std::max(maxForce, d.contact.magnitudeN);
    refinedSeen = std::max(refinedSeen, d.refinedCount);
    ++frames;
    std::this_thread::sleep_for(std::chrono::milliseconds(16));
  }
  const RuntimeResult r = live.stop();
  EXPECT_FALSE(live.running());
  EXPECT_GT(r.stats.collisionSteps, 800u);
  EXPECT_GT(maxForce, 0.5);
  EXPECT_GT(refinedSeen, 0u);
  EXPECT_EQ(everything, 1u);
  EXPECT_GT(changedFrames, 0u);
  EXPECT_GT(r.stats.firstStepNs, 0);
  EXPECT_GT(r.stats.surfaceReadyNs, 0);
  EXPECT_GT(frames, 20u);
  EXPECT_GT(session.removedVolumeMm3(), 0.0);
  // After stop the visual surface and the session's own are the drilled grid's surface.
  const geometry::SurfaceMesh full =
      geometry::extractSurface(session.grid(), geometry::SurfaceOptions{});
  EXPECT_EQ(live.visualSurface().triangleCount(), full.triangleCount());
  EXPECT_EQ(session.surface().triangleCount(), full.triangleCount());
}

// A pose source that notes what the haptic loop does to it: calls at once on two threads, or
// a period given twice or out of order.
class WatchingSource : public PoseSource {
 public:
  void sample(double tS, ToolPose& pose, bool& drillOn) noexcept override {
    if (inside_.fetch_add(1) != 0) overlapped_ = true;
    if (tS <= lastTS_) backwards_ = true;
    lastTS_ = tS;
    pose = ToolPose{};
    pose.tipMm = glm::dvec3(0.0, 0.0, 500.0);  // far above the bone: no contact
    drillOn = false;
    inside_.fetch_sub(1);
  }
  bool overlapped() const { return overlapped_.load(); }
  bool backwards() const { return backwards_; }

 private:
  std::atomic<int> inside_{0};
  std::atomic<bool> overlapped_{false};
  double lastTS_ = -1.0;
  bool backwards_ = false;
};

// The standby tests' bone: coarse, since they watch the haptic loop, not the drilling.
Session coarseHumerus() {
  SessionOptions options;
  options.voxelSizeMm = 2.4;
  return test::humerusSession(options);
}

RuntimeOptions withoutLog() {
  RuntimeOptions ro;
  ro.keepLog = false;
  return ro;
}

// Starts `live` and waits until its haptic loop ran `steps` periods; false, with the runtime
// stopped, when the loop has no standby thread (one CPU).
bool startWithStandby(LiveRuntime& live, std::uint64_t steps) {
  live.start();
  while (live.stats().hapticSteps < steps)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  if (live.stats().standbyCpu >= 0) return true;
  live.stop();
  return false;
}

// A real-time thread holds the first haptic thread's CPU for 200 ms: the standby, pinned to
// another CPU, must run those periods, each once and in order, and never beside the first.
TEST(LiveRuntime, TheHapticStandbyRunsThePeriodsOfAHeldCpu) {
  Session session = coarseHumerus();
  WatchingSource source;
  LiveRuntime live(session, source, nullptr, withoutLog());
  if (!startWithStandby(live, 100))
    GTEST_SKIP() << "one CPU: the haptic loop has no standby thread";
  const LiveStats before = live.stats();
  std::atomic<int> hogStarted{0};  // 1: holding the CPU; -1: real-time priority refused
  std::thread hog([&] {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(std::size_t(before.hapticCpu), &set);
    pthread_setaffinity_np(pthread_self(), sizeof set, &set);
    sched_param p{};
    p.sched_priority = 90;  // above the haptic threads' 80
    if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &p) != 0) {
      hogStarted = -1;
      return;
    }
    hogStarted = 1;
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
    while (std::chrono::steady_clock::now() < until) {
    }
  });
  while (hogStarted == 0) std::this_thread::yield();
  hog.join();
  const LiveStats after = live.stats();
  const RuntimeResult r = live.stop();
  if (hogStarted < 0 || !r.stats.realtimeGranted)
    GTEST_SKIP() << "SCHED_FIFO not granted: no CPU can be held";
  EXPECT_NE(before.hapticCpu, before.standbyCpu);
  // About 200 periods passed while the CPU was held; without the standby hardly any would run.
  EXPECT_GE(after.hapticSteps - before.hapticSteps, 180u);
  EXPECT_GE(after.standbySteps - before.standbySteps, 150u);
  EXPECT_FALSE(source.overlapped());
  EXPECT_FALSE(source.backwards());
}

// A pose source whose one call, when asked, stalls 100 ms as a paused vCPU would, and notes
// the CPU time the whole process used meanwhile.
class StallingSource : public PoseSource {
 public:
  void sample(double, ToolPose& pose, bool& drillOn) noexcept override {
    pose = ToolPose{};
    pose.tipMm = glm::dvec3(0.0, 0.0, 500.0);  // far above the bone: no contact
    drillOn = false;
    if (stallNext_.exchange(false)) {
      const double cpu0 = processCpuS();
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      cpuDuringStallS_ = processCpuS() - cpu0;
      stalled_ = true;
    }
  }
  void stallNext() { stallNext_ = true; }
  bool stalled() const { return stalled_.load(); }
  double cpuDuringStallS() const { return cpuDuringStallS_.load(); }

 private:
  static double processCpuS() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
  }
  std::atomic<bool> stallNext_{false}, stalled_{false};
  std::atomic<double> cpuDuringStallS_{0.0};
};

// While one haptic thread is stalled inside a period's work, the other may not run periods
// (never both at once) and must sleep a period at a time, not spin on the claim: a spinning
// real-time thread would take its CPU from the collision loop for the whole stall.
TEST(LiveRuntime, TheHapticStandbySleepsWhileTheOtherThreadIsStalledInItsWork) {
  Session session = coarseHumerus();
  StallingSource source;
  LiveRuntime live(session, source, nullptr, withoutLog());
  if (!startWithStandby(live, 50)) GTEST_SKIP() << "one CPU: the haptic loop has no standby thread";
  source.stallNext();
  while (!source.stalled()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const std::uint64_t stepsAfterStall = live.stats().hapticSteps;
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const RuntimeResult r = live.stop();
  // The 1 kHz loops with no contact use a few ms of CPU in 100 ms; a spin would use 100.
  EXPECT_LT(source.cpuDuringStallS(), 0.05);
  EXPECT_GE(r.stats.hapticOverruns, 1u);                 // the stalled period
  EXPECT_GT(r.stats.hapticSteps, stepsAfterStall + 20);  // and the loop went on after it
}

}  // namespace
}  // namespace osteon::simulation
