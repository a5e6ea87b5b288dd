// The live runtime a viewer drives: the 1 kHz loops in their threads, the visual work on the
// caller's thread through hand-offs only.
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/simulation/live.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace osteon::simulation {
namespace {

TEST(LiveRuntime, DrillsWhileTheCallerRendersAndEndsEqualToTheGrid) {
  SessionOptions options;
  Session session = Session::fromMesh(geometry::defaultHumerusModel().mesh, options, "default");
  PortalPathOptions po;
  po.durationS = 1.2;
  const DrillPath path = session.portalPath(Portal::FiveOClock, po).path;
  PathPoseSource source(path);
  RuntimeOptions ro;
  ro.realtimePriority = false;
  ro.keepLog = false;
  LiveRuntime live(session, source, nullptr, ro);
  EXPECT_TRUE(live.takeSurfaceChanges().everything);  // the first read: the whole surface
  live.start();
  EXPECT_TRUE(live.running());
  std::size_t frames = 0, changedFrames = 0, refinedSeen = 0;
  double maxForce = 0.0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(1600);
  while (std::chrono::steady_clock::now() < until) {  // a render loop at about 60 Hz
    live.updateSurface();
    const SurfaceChanges c = live.takeSurfaceChanges();
    EXPECT_FALSE(c.everything);
    changedFrames += c.bricks.empty() ? 0 : 1;
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
  EXPECT_GT(changedFrames, 0u);
  EXPECT_GT(frames, 20u);
  EXPECT_GT(session.removedVolumeMm3(), 0.0);
  // After stop the visual surface and the session's own are the drilled grid's surface.
  const geometry::SurfaceMesh full = geometry::extractSurface(session.grid(), geometry::SurfaceOptions{});
  EXPECT_EQ(live.visualSurface().triangleCount(), full.triangleCount());
  EXPECT_EQ(session.surface().triangleCount(), full.triangleCount());
}

}  // namespace
}  // namespace osteon::simulation
