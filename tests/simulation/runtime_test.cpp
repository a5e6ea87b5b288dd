#include "osteon/simulation/runtime.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <thread>

#include <gtest/gtest.h>

#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/session.h"
#include "support/humerus_session.h"

namespace osteon::simulation {
namespace {

// The built-in humerus voxelized at 1.2 mm (a bone from a grid: refined voxels split their
// fill evenly), and a short, fast portal-5 path: bone within the first second.
struct HumerusRun {
  Session session = test::humerusGridSession();
  PortalPlan plan = test::humerusMeshPortalPlan(session, 1.5);
};

TEST(Runtime, ThreeThreadsDrillAndTheVisualSurfaceMatchesTheGrid) {
  HumerusRun h;
  PathPoseSource source(h.plan.path);
  struct Sink : ForceSink {
    double maxN = 0.0;
    void apply(double, const glm::dvec3& f) noexcept override {
      maxN = std::max(maxN, glm::length(f));
    }
  } sink;
  RuntimeOptions options;
  options.durationS = 1.5;
  options.realtimePriority = false;
  const std::int64_t beganNs = std::chrono::steady_clock::now().time_since_epoch().count();
  const RuntimeResult r = h.session.runThreaded(source, &sink, options);
  const std::int64_t endedNs = std::chrono::steady_clock::now().time_since_epoch().count();
  // Shared, noisy machines miss periods; the loops skip them rather than fall behind. Each
  // overrun's instant is kept, in order, within the run.
  for (const auto& [instants, count] :
       {std::pair{&r.stats.hapticOverrunNs, r.stats.hapticOverruns},
        std::pair{&r.stats.collisionOverrunNs, r.stats.collisionOverruns}}) {
    EXPECT_EQ(instants->size(), std::min<std::uint64_t>(count, RuntimeStats::kOverrunInstantsKept));
    EXPECT_TRUE(std::is_sorted(instants->begin(), instants->end()));
    for (const std::int64_t t : *instants) EXPECT_TRUE(t > beganNs && t < endedNs);
  }
  EXPECT_GT(r.stats.collisionSteps, 750u);
  EXPECT_LE(r.stats.collisionSteps, 1501u);
  EXPECT_EQ(r.stats.logDropped, 0u);
  EXPECT_GT(h.session.totals().removedFill, 0u);
  EXPECT_GT(r.stats.bricksHandedOver, 0u);
  EXPECT_GT(sink.maxN, 0.1);  // forces reached the device
  EXPECT_LE(sink.maxN, 3.3 + 1e-12);
  // The visual thread's incremental surface equals a full extraction of the drilled grid.
  const geometry::SurfaceMesh& surface = h.session.surface();
  const geometry::SurfaceMesh full =
      geometry::extractSurface(h.session.grid(), geometry::SurfaceOptions{});
  EXPECT_EQ(surface.triangleCount(), full.triangleCount());
  EXPECT_EQ(surface.vertexCount(), full.vertexCount());
  EXPECT_NEAR(geometry::signedVolumeMm3(surface.toTriangleMesh()),
              geometry::signedVolumeMm3(full.toTriangleMesh()),
              1e-6 * std::abs(geometry::signedVolumeMm3(full.toTriangleMesh())));
}

// The collision thread hands rows to a logging thread: with keepLog off nothing is collected,
// every row reaches onRow in order, and the summary is the metrics of those rows.
TEST(Runtime, StreamsTheForceLogWithoutKeepingIt) {
  HumerusRun h;
  PathPoseSource source(h.plan.path);
  RuntimeOptions options;
  options.durationS = 2.2;  // past 2 s, so the jitter window has rows
  options.realtimePriority = false;
  options.keepLog = false;
  std::vector<ForceLogRow> rows;
  rows.reserve(3000);
  options.onRow = [&](const ForceLogRow& r) { rows.push_back(r); };
  const RuntimeResult r = h.session.runThreaded(source, nullptr, options);
  EXPECT_TRUE(r.run.log.empty());
  EXPECT_EQ(r.run.log.capacity(), 0u);
  EXPECT_EQ(r.stats.logDropped, 0u);
  ASSERT_GT(rows.size(), 1000u);
  EXPECT_LE(rows.size(), r.stats.collisionSteps);
  for (std::size_t i = 1; i < rows.size(); ++i) ASSERT_GE(rows[i].tS, rows[i - 1].tS);
  double maxForce = 0.0;
  for (const ForceLogRow& row : rows) maxForce = std::max(maxForce, row.magnitudeN);
  EXPECT_GT(maxForce, 0.1);
  EXPECT_EQ(r.run.summary.maxForceN, maxForce);
  EXPECT_EQ(r.run.summary.jitterN, forceJitterN(rows));
  EXPECT_EQ(r.run.summary.maxStepChangeN, maxStepChangeN(rows));
  EXPECT_GT(r.run.summary.hapticStepUs.max, 0.0);
}

}  // namespace
}  // namespace osteon::simulation
