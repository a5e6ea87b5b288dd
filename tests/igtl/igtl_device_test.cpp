// `igtl:HOST:PORT[/NAME]` against a tracker written with the reference library (its
// ServerSocket and TransformMessage): poses come in RAS and go out in LPS, a stream that stops
// is a safety fault (a gap), and a stream of a path drives a run to the path's removed volume.
#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "igtlServerSocket.h"
#include "igtlTransformMessage.h"
#include "osteon/core/error.h"
#include "osteon/devices/device.h"
#include "osteon/simulation/device_input.h"
#include "osteon/simulation/session.h"
#include "support/humerus_session.h"

namespace osteon::devices {
namespace {

using namespace osteon::simulation;

// Streams the pose of `poseAt(t)` (LPS, converted here to RAS) as TRANSFORM `name` every
// millisecond of wall time for durationS, then holds the connection for holdS without sending.
class Tracker {
 public:
  Tracker(int port, std::function<ToolPose(double)> poseAt, double durationS, double holdS)
      : poseAt_(std::move(poseAt)) {
    server_ = ::igtl::ServerSocket::New();
    server_->CreateServer(port);
    thread_ = std::thread([this, durationS, holdS] { serve(durationS, holdS); });
  }
  ~Tracker() { thread_.join(); }

 private:
  void serve(double durationS, double holdS) {
    ::igtl::Socket::Pointer socket;
    for (int i = 0; i < 500 && !socket; ++i) socket = server_->WaitForConnection(10);
    if (!socket) return;
    const auto start = std::chrono::steady_clock::now();
    for (double t = 0.0; t <= durationS;
         t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()) {
      const ToolPose p = poseAt_(t);
      const glm::dmat3 r = glm::mat3_cast(p.orientation);
      const glm::dvec3 f(-1.0, -1.0, 1.0);
      ::igtl::Matrix4x4 m;
      ::igtl::IdentityMatrix(m);
      for (int row = 0; row < 3; ++row) {
        for (int c = 0; c < 3; ++c) m[row][c] = static_cast<float>(f[row] * r[c][row] * f[c]);
        m[row][3] = static_cast<float>(f[row] * p.tipMm[row]);
      }
      ::igtl::TransformMessage::Pointer msg = ::igtl::TransformMessage::New();
      msg->SetDeviceName("DrillToRAS");
      msg->SetMatrix(m);
      msg->Pack();
      socket->Send(msg->GetPackPointer(), msg->GetPackSize());
      std::this_thread::sleep_for(std::chrono::microseconds(900));
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(holdS));
    socket->CloseSocket();
  }

  std::function<ToolPose(double)> poseAt_;
  ::igtl::ServerSocket::Pointer server_;
  std::thread thread_;
};

TEST(IgtlDevice, TakesRasTransformsAsLpsPosesAndGoesSilentWhenTheStreamStops) {
  ToolPose pose = ToolPose::pointing({10.0, -20.0, 30.0}, {1.0, 2.0, -3.0});
  Tracker tracker(
      18990, [pose](double) { return pose; }, 0.3, 0.7);
  std::unique_ptr<Device> device = openDevice("igtl:127.0.0.1:18990/DrillToRAS");
  EXPECT_TRUE(device->capabilities().pose);
  DeviceSample s;
  double lastNewS = -1.0;
  const auto start = std::chrono::steady_clock::now();
  double t = 0.0;
  while (t < 0.9) {
    t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    device->poll(t, s);
    if (s.tS == t) lastNewS = t;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_GE(s.tS, 0.0);
  EXPECT_NEAR(glm::length(s.positionMm - pose.tipMm), 0.0, 1e-4);
  EXPECT_NEAR(std::abs(glm::dot(s.orientation, pose.orientation)), 1.0, 1e-5);
  EXPECT_TRUE(s.drillOn);
  // Fresh at each poll while the stream flows, ageing 250 ms after it stopped at 0.3 s.
  EXPECT_GT(lastNewS, 0.45);
  EXPECT_LT(lastNewS, 0.75);
}

// Through DeviceInput: a stream that stops mid-run is a safety-layer fault (a gap).
TEST(IgtlDevice, AStreamThatStopsIsASafetyFault) {
  SessionOptions options;
  options.levels = 0;
  Session session = test::humerusSession(options);
  const ToolPose pose = ToolPose::pointing({0.0, 0.0, 200.0}, {0.0, 0.0, -1.0});  // off the bone
  Tracker tracker(
      18993, [pose](double) { return pose; }, 0.4, 1.0);
  std::unique_ptr<Device> device = openDevice("igtl:127.0.0.1:18993");
  DeviceInput input(*device);
  RuntimeOptions ro;
  ro.durationS = 1.0;
  ro.realtimePriority = false;
  ro.keepLog = false;
  session.runThreaded(input, &input, ro);
  EXPECT_TRUE(input.hasPose());
  EXPECT_GT(input.safety().stats().faults.gaps, 0u);
  EXPECT_GT(input.safety().stats().heldSteps, 100u);  // the tool held from ~0.65 s to 1 s
}

TEST(IgtlDevice, RefusesMalformedAddressesAndAnAddressWhereNothingListens) {
  for (const char* name : {"igtl:", "igtl:localhost", "igtl:localhost:0", "igtl:h:99999",
                           "igtl:127.0.0.1:18991/", "igtl:127.0.0.1:18991"}) {
    EXPECT_THROW(openDevice(name), InputError) << name;
  }
}

// The portal-5 path streamed by a tracker drives a threaded run (direct coupling) to the
// removed volume the path removes by itself.
TEST(IgtlDevice, AStreamedPathRemovesWhatThePathRemoves) {
  SessionOptions options;
  options.levels = 0;
  Session reference = test::humerusSession(options);
  const DrillPath path = test::portalFivePath(reference, 3.0);
  reference.run(path);
  const double wantMm3 = reference.removedVolumeMm3();

  Session session = test::humerusSession(options);
  auto poseAt = [&path](double t) {
    ToolPose p;
    bool on = false;
    path.sample(t, p, on);
    return p;
  };
  Tracker tracker(18992, poseAt, path.durationS() + 0.2, 0.2);
  std::unique_ptr<Device> device = openDevice("igtl:127.0.0.1:18992");
  DeviceInput input(*device);
  RuntimeOptions ro;
  ro.durationS = path.durationS();
  ro.realtimePriority = false;
  ro.keepLog = false;
  session.runThreaded(input, &input, ro);
  const double gotMm3 = session.removedVolumeMm3();
  std::printf("[ igtl     ] removed %.2f mm3 streamed, %.2f mm3 from the path\n", gotMm3, wantMm3);
  EXPECT_GT(wantMm3, 1.0);
  EXPECT_NEAR(gotMm3, wantMm3, 0.1 * wantMm3);
}

}  // namespace
}  // namespace osteon::devices
