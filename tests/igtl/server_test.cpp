// osteon's OpenIGTLink server on 127.0.0.1, read by a client written with the reference
// library (igtl_client.h): the volume it rebuilds is the drilled grid, the transforms follow
// the path, and a client that stops reading does not slow the haptic loop.
#include "osteon/igtl/server.h"

#include <algorithm>
#include <cstdio>
#include <future>
#include <netinet/in.h>
#include <sys/socket.h>
#include <thread>
#include <unistd.h>

#include <gtest/gtest.h>

#include "igtl/igtl_client.h"
#include "osteon/simulation/runtime.h"
#include "osteon/simulation/session.h"
#include "support/humerus_session.h"

namespace osteon::igtl {
namespace {

using namespace osteon::simulation;

constexpr double kPathS = 3.0;

RuntimeOptions runOptions(double durationS) {
  RuntimeOptions ro;
  ro.durationS = durationS;
  ro.realtimePriority = false;
  ro.keepLog = false;
  return ro;
}

ServerOptions anyPort() {
  ServerOptions o;
  o.port = 0;
  return o;
}

RuntimeResult runServed(Session& session, const DrillPath& path, Server& server) {
  PathPoseSource source(path);
  RuntimeOptions ro = runOptions(path.durationS());
  ro.onVisual = [&server](LiveRuntime& live, bool last) { server.publish(live, last); };
  return session.runThreaded(source, nullptr, ro);
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p * double(v.size())))];
}

TEST(IgtlServer, AClientRebuildsTheDrilledGridFromImageMessages) {
  SessionOptions options;
  options.levels = 0;
  Session session = test::humerusSession(options);
  const DrillPath path = test::portalFivePath(session, kPathS);
  const geometry::VoxelGrid before = session.grid();
  Server server(anyPort(), session.simulation().tool());
  auto client = std::async(std::launch::async, [&] { return test::receiveAll(server.port()); });
  // The client is connected before the run starts (it retries until it is).
  while (server.stats().clients == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const RuntimeResult run = runServed(session, path, server);
  const ServerStats stats = server.stop();
  const test::IgtlReceived got = client.get();

  const geometry::VoxelGrid& grid = session.grid();
  ASSERT_EQ(got.dims, grid.dims());
  EXPECT_FLOAT_EQ(got.spacing[0], float(grid.voxelSizeMm()));
  EXPECT_EQ(got.wholeVolumes, 1);
  EXPECT_GT(got.subVolumes, 2);  // up to 10 Hz over a 3 s run
  EXPECT_GT(run.run.summary.removedVolumeMm3, 1.0);
  std::size_t differ = 0, drilled = 0;
  const glm::ivec3 d = grid.dims();
  for (int z = 0; z < d.z; ++z) {
    for (int y = 0; y < d.y; ++y) {
      for (int x = 0; x < d.x; ++x) {
        const auto want = std::uint8_t(grid.fill({x, y, z}) / geometry::kFillPerStep);
        const std::size_t i =
            std::size_t(x) +
            std::size_t(d.x) * (std::size_t(y) + std::size_t(d.y) * std::size_t(z));
        differ += got.volume[i] != want ? 1u : 0u;
        drilled += before.fill({x, y, z}) != grid.fill({x, y, z}) ? 1u : 0u;
      }
    }
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(drilled, 10u);  // the run changed the grid, and the client saw it
  EXPECT_EQ(stats.dropped, 0u);
  EXPECT_EQ(std::count(got.polydata.begin(), got.polydata.end(), "DrillModel"), 1);
  EXPECT_FALSE(got.strings.empty());
}

TEST(IgtlServer, TransformsFollowThePathInRas) {
  SessionOptions options;
  options.levels = 0;
  Session session = test::humerusSession(options);
  const DrillPath path = test::portalFivePath(session, kPathS);
  Server server(anyPort(), session.simulation().tool());
  auto client = std::async(std::launch::async, [&] { return test::receiveAll(server.port()); });
  while (server.stats().clients == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  runServed(session, path, server);
  server.stop();
  const test::IgtlReceived got = client.get();

  // 100 Hz at most; over a 3 s run, well above a few dozen even on a loaded machine.
  EXPECT_GT(got.transforms.size(), 60u);
  EXPECT_LE(double(got.transforms.size()), 100.0 * kPathS * 1.1 + 2.0);
  std::vector<glm::dvec3> samples;
  for (double t = 0.0; t <= path.durationS(); t += 0.001) {
    ToolPose pose;
    bool on = false;
    path.sample(t, pose, on);
    samples.push_back(pose.tipMm);
  }
  double worstMm = 0.0;
  for (const test::ReceivedTransform& rt : got.transforms) {
    const glm::dvec3 lps(-rt.matrix[3].x, -rt.matrix[3].y, rt.matrix[3].z);  // RAS -> LPS
    double best = 1e9;
    for (const glm::dvec3& s : samples) best = std::min(best, glm::length(s - lps));
    worstMm = std::max(worstMm, best);
    EXPECT_NEAR(glm::determinant(glm::dmat3(rt.matrix)), 1.0, 1e-4);  // a rotation
  }
  EXPECT_LT(worstMm, 0.01);
  const double spanS = std::max(1e-9, got.lastS - got.firstS);
  std::printf(
      "[ igtl     ] %zu transforms, %llu messages in %.2f s: %.0f messages/s, %.0f bytes/s, "
      "latency p50 %.3f ms p99 %.3f ms\n",
      got.transforms.size(), static_cast<unsigned long long>(got.messages), spanS,
      double(got.messages) / spanS, double(got.bytes) / spanS,
      1e3 * percentile(got.latenciesS, 0.5), 1e3 * percentile(got.latenciesS, 0.99));
}

// A score sent once reaches the client connected then and one that connects later.
TEST(IgtlServer, KeptStringsReachClientsThatConnectLater) {
  SessionOptions options;
  options.levels = 0;
  Session session = test::humerusSession(options);
  const DrillPath path = test::portalFivePath(session, 1.0);
  Server server(anyPort(), session.simulation().tool());
  auto early = std::async(std::launch::async, [&] { return test::receiveAll(server.port()); });
  while (server.stats().clients == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  server.sendString("Score", "first");
  server.sendString("Score", "PASSED, score 90 / 100");
  auto late = std::async(std::launch::async, [&] { return test::receiveAll(server.port()); });
  while (server.stats().clients < 2) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  runServed(session, path, server);
  server.stop();
  const std::vector<std::string> a = early.get().strings, b = late.get().strings;
  const auto count = [](const std::vector<std::string>& v, const std::string& s) {
    return std::count(v.begin(), v.end(), s);
  };
  EXPECT_EQ(count(a, "Score=first"), 1);
  EXPECT_EQ(count(a, "Score=PASSED, score 90 / 100"), 1);
  EXPECT_EQ(count(b, "Score=first"), 0);  // only the latest text of a name is kept
  EXPECT_EQ(count(b, "Score=PASSED, score 90 / 100"), 1);
}

// A raw TCP client that connects and never reads: its queue fills, messages are dropped, and
// the haptic loop's overruns stay those of a run with no client at all.
TEST(IgtlServer, AClientThatStopsReadingDoesNotSlowTheHapticLoop) {
  SessionOptions options;
  options.levels = 0;
  Session plain = test::humerusSession(options);
  const DrillPath path = test::portalFivePath(plain, kPathS);
  PathPoseSource source(path);
  const RuntimeResult floor = plain.runThreaded(source, nullptr, runOptions(kPathS));

  Session session = test::humerusSession(options);
  ServerOptions so = anyPort();
  so.queueMessages = 16;
  so.sendBufferBytes = 4096;
  Server server(so, session.simulation().tool());
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  const int small = 4096;
  ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(server.port()));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  while (server.stats().clients == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const RuntimeResult run = runServed(session, path, server);
  const ServerStats stats = server.stop(0.2);
  ::close(fd);

  EXPECT_GT(stats.dropped, 0u);
  EXPECT_GT(stats.volumesSent, 1u);  // dropped image updates: the whole volume queued again
  // Every period run (a missed period is skipped, never run late): the run kept its pace.
  EXPECT_NEAR(double(run.stats.hapticSteps), double(floor.stats.hapticSteps),
              0.01 * 1000.0 * kPathS);
  std::printf(
      "[ igtl     ] haptic overruns: %llu with a stalled client, %llu without; %llu dropped\n",
      static_cast<unsigned long long>(run.stats.hapticOverruns),
      static_cast<unsigned long long>(floor.stats.hapticOverruns),
      static_cast<unsigned long long>(stats.dropped));
  // A loop that waited on the client would overrun for most of the 3000 periods; a shared
  // machine's noise moves either run by tens, so the floor gets that much room.
  EXPECT_LE(double(run.stats.hapticOverruns), 1.5 * double(floor.stats.hapticOverruns) + 30.0);
}

}  // namespace
}  // namespace osteon::igtl
