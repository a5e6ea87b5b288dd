// The live runtime's loops (haptic, collision) and its logging thread allocate nothing once
// warmed up, while they drill and the caller's render loop (which may allocate) takes the
// surface. Its own program, as it counts every heap allocation (support/allocation_counter).
#include <chrono>
#include <cstdint>
#include <thread>

#include <gtest/gtest.h>

#include "osteon/geometry/io/humerus_model.h"
#include "osteon/simulation/live.h"
#include "support/allocation_counter.h"
#include "support/humerus_session.h"

namespace osteon::simulation {
namespace {

// Allocations by every thread but the calling one.
std::uint64_t otherThreadsAllocations() {
  return test::allocations() - test::threadAllocations();
}

TEST(LiveAllocation, TheCounterSeesAnotherThreadsAllocations) {
  const std::uint64_t before = otherThreadsAllocations();
  std::thread other([] {
    static int* volatile kept = nullptr;  // volatile: the allocation cannot be elided
    kept = new int(1);
    delete kept;
  });
  other.join();
  EXPECT_GE(otherThreadsAllocations() - before, 1u);
}

TEST(LiveAllocation, TheLoopsAllocateNothingOnceWarmedUpWhileTheyDrill) {
  Session session = test::humerusSession();
  PortalPathOptions po;
  po.durationS = 3.0;  // bone within the first second, drilled on to the end
  const DrillPath path = session.portalPath(Portal::FiveOClock, po).path;
  PathPoseSource source(path);
  struct Sink : ForceSink {
    double maxN = 0.0;
    void apply(double, const glm::dvec3& f) noexcept override {
      maxN = std::max(maxN, glm::length(f));
    }
  } sink;
  RuntimeOptions ro;
  ro.realtimePriority = false;
  ro.keepLog = false;  // the log would grow past its reserve in a long session: streamed instead
  LiveRuntime live(session, source, &sink, ro);
  live.start();
  const auto render =
      [&live](std::chrono::milliseconds forMs) {  // the caller's frames at about 60 Hz
        const auto until = std::chrono::steady_clock::now() + forMs;
        while (std::chrono::steady_clock::now() < until) {
          live.updateSurface();
          std::this_thread::sleep_for(std::chrono::milliseconds(16));
        }
      };
  render(std::chrono::milliseconds(400));  // warm-up: first touches, the first contact
  const LiveStats before = live.stats();
  const std::uint64_t removedBefore = live.display().removedFill;
  const std::uint64_t allocationsBefore = otherThreadsAllocations();
  render(std::chrono::milliseconds(1500));
  const std::uint64_t inLoops = otherThreadsAllocations() - allocationsBefore;
  const LiveStats after = live.stats();
  const std::uint64_t removedAfter = live.display().removedFill;
  live.stop();
  EXPECT_EQ(inLoops, 0u);
  // The loops did the work in that window: periods run, bone removed, bricks handed over.
  EXPECT_GT(after.collisionSteps - before.collisionSteps, 500u);
  EXPECT_GT(after.hapticSteps - before.hapticSteps, 500u);
  EXPECT_GT(removedAfter, removedBefore);
  EXPECT_GT(after.bricksHandedOver, before.bricksHandedOver);
  EXPECT_GT(sink.maxN, 0.1);
}

}  // namespace
}  // namespace osteon::simulation
