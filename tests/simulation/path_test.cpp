#include "osteon/simulation/path.h"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh_io.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon::simulation {
namespace {

TEST(HumeralHead, FitFindsTheBuiltInModelsHeadAndFrame) {
  const geometry::HumerusModel model = geometry::buildHumerusModel();
  const HumeralHead head = fitHumeralHead(model.mesh);
  EXPECT_LT(glm::length(head.centreMm - model.headCentreMm), 1.0);
  EXPECT_NEAR(head.radiusMm, model.headRadiusMm, 1.0);
  EXPECT_GT(glm::dot(head.superior, model.shaftAxis), 0.99);
  EXPECT_GT(glm::dot(head.axis, model.headAxis), 0.97);  // through the articular cap
  // LPS, right humerus: medial +x, anterior -y.
  EXPECT_GT(head.medial.x, 0.9);
  EXPECT_LT(head.anterior.y, -0.9);
  EXPECT_GT(fitHumeralHead(model.mesh, false).anterior.y, 0.9);
}

TEST(HumeralHead, FitFindsTheHeadOfTheSharedHumerusInMetres) {
  const std::string file = std::string(OSTEON_SHARED_DATA_DIR) + "/humerus_R_opensim_myosuite.stl";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "shared data not found: " << file;
  const geometry::TriangleMesh mesh = geometry::readMesh(file, 1000.0);
  const HumeralHead head = fitHumeralHead(mesh);
  // The README gives the head as about 43 mm across.
  EXPECT_NEAR(2.0 * head.radiusMm, 43.0, 6.0);
  EXPECT_LT(head.rmsResidualMm, 1.5);
  // The head is at the end of the bone superior points to.
  const geometry::Aabb box = geometry::bounds(mesh);
  const glm::dvec3 mid = 0.5 * (box.minMm + box.maxMm);
  EXPECT_GT(glm::dot(head.centreMm - mid, head.superior), 100.0);
}

TEST(Portal, PathsEnterTheHeadAtTheirClockPositionAt45Degrees) {
  const geometry::HumerusModel model = geometry::buildHumerusModel();
  const HumeralHead head = fitHumeralHead(model.mesh);
  const PortalPlan five = makePortalPath(Portal::FiveOClock, head, model.mesh, 2.06);
  const PortalPlan seven = makePortalPath(Portal::SevenOClock, head, model.mesh, 2.06);
  for (const PortalPlan* p : {&five, &seven}) {
    EXPECT_NEAR(glm::dot(-p->direction, p->normal), std::cos(M_PI / 4), 1e-9);
    // On the articular cap, below its pole; the hole stays in the head.
    EXPECT_NEAR(glm::dot(p->clockDirection, head.axis), std::cos(M_PI / 4), 1e-9);
    EXPECT_LT(glm::dot(p->clockDirection, head.superior), glm::dot(head.axis, head.superior));
    EXPECT_NEAR(p->path.durationS(), 7.0, 1e-12);
    ToolPose pose;
    bool on = false;
    p->path.sample(0.0, pose, on);
    EXPECT_TRUE(on);
    // The cushion starts clear of the bone: no voxel of the mesh within its reach.
    double nearest = 1e300;
    for (const glm::dvec3& v : model.mesh.positionsMm)
      nearest = std::min(nearest, glm::length(v - pose.tipMm));
    EXPECT_GT(nearest, 2.06) << "start inside or touching the bone";
    EXPECT_NEAR(glm::length(pose.forward() - p->direction), 0.0, 1e-9);
    p->path.sample(7.0, pose, on);
    EXPECT_NEAR(glm::length(pose.tipMm - p->entryMm), 15.0, 1e-9);
    EXPECT_LT(glm::length(pose.tipMm - head.centreMm), head.radiusMm - 5.0);  // deep in the head
  }
  // 5 o'clock anteroinferior, 7 o'clock posteroinferior: mirror images across the 6 o'clock line.
  EXPECT_GT(glm::dot(five.clockDirection - seven.clockDirection, head.anterior), 0.5);
  EXPECT_NEAR(glm::dot(five.clockDirection, head.superior),
              glm::dot(seven.clockDirection, head.superior), 1e-9);
  EXPECT_THROW(parsePortal("portal-6"), InputError);
}

TEST(PathCsv, ReadsPathsAndRejectsBadRowsNamingTheLine) {
  const std::string dir = test::makeTempDir("path_csv");
  const std::string good = dir + "/good.csv";
  test::writeBytes(good, "t,x,y,z,drill_on\n0,0,0,10,0\n1,0,0,0,1\n2,0,0,-10,1\n");
  const DrillPath path = loadPathCsv(good);
  ToolPose pose;
  bool on = true;
  path.sample(0.5, pose, on);
  EXPECT_FALSE(on);
  EXPECT_NEAR(pose.tipMm.z, 5.0, 1e-12);
  EXPECT_NEAR(pose.forward().z, -1.0, 1e-12);  // along the travel
  path.sample(1.5, pose, on);
  EXPECT_TRUE(on);
  const std::string quat = dir + "/quat.csv";
  test::writeBytes(quat, "t,x,y,z,drill_on,qw,qx,qy,qz\n0,0,0,0,1,1,0,0,0\n1,1,0,0,1,0,1,0,0\n");
  EXPECT_EQ(loadPathCsv(quat).points().size(), 2u);
  const auto expectError = [&](const std::string& text, const std::string& fragment) {
    const std::string f = dir + "/bad.csv";
    test::writeBytes(f, text);
    try {
      loadPathCsv(f);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  };
  expectError("", "empty");
  expectError("time,x,y,z,drill_on\n", "header");
  expectError("t,x,y,z,drill_on\n0,0,0,0,1\n0.5,0,zero,0,1\n", ":3:");
  expectError("t,x,y,z,drill_on\n0,0,0,0,1\n0,1,0,0,1\n", "increase");
  expectError("t,x,y,z,drill_on\n0,0,0,0,2\n1,0,0,0,1\n", "drill_on");
  expectError("t,x,y,z,drill_on\n0,0,0,0,1\n1,0,0\n", "expected 5");
  expectError("t,x,y,z,drill_on\n0,0,0,0,1\n", "two rows");
  expectError("t,x,y,z,drill_on,qw,qx,qy,qz\n0,0,0,0,1,0,0,0,0\n1,0,0,0,1,1,0,0,0\n", "zero");
  EXPECT_THROW(loadPathCsv(dir + "/missing.csv"), InputError);
}

// A path's end time sizes the run: an hour at most, refused naming the row and the limit.
TEST(PathCsv, RefusesPathsLongerThanTheLimitNamingTheRowAndTheLimit) {
  const std::string dir = test::makeTempDir("path_csv_duration");
  const std::string file = dir + "/long.csv";
  for (const char* end : {"1e300", "1e12", "100000", "3600.001"}) {
    test::writeBytes(file,
                     std::string("t,x,y,z,drill_on\n0,0,0,0,1\n1,0,0,1,1\n") + end + ",0,0,2,1\n");
    try {
      loadPathCsv(file);
      ADD_FAILURE() << "accepted a path ending at t = " << end;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file + ":4:"), std::string::npos) << what;
      EXPECT_NE(what.find("3600 s"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos);
    }
  }
  test::writeBytes(file, "t,x,y,z,drill_on\n0,0,0,0,1\n3600,0,0,1,1\n");
  EXPECT_EQ(loadPathCsv(file).durationS(), kMaxPathDurationS);
}

// Quaternions are scaled by their largest component first: huge or tiny ones give the same
// orientation as their unit multiple.
TEST(PathCsv, NormalisesHugeAndTinyQuaternionsWithoutOverflow) {
  const std::string dir = test::makeTempDir("path_csv_quat");
  const auto orientationOf = [&](const std::string& q) {
    const std::string file = dir + "/q.csv";
    test::writeBytes(file,
                     "t,x,y,z,drill_on,qw,qx,qy,qz\n0,0,0,0,1," + q + "\n1,1,0,0,1," + q + "\n");
    return loadPathCsv(file).points().front().orientation;
  };
  const glm::dquat unit = orientationOf("1,1,0,0");
  EXPECT_NEAR(unit.w, std::sqrt(0.5), 1e-15);
  for (const char* q :
       {"1e300,1e300,0,0", "-1e308,-1e308,0,0", "1e-300,1e-300,0,0", "3e-308,3e-308,0,0"}) {
    const glm::dquat o = orientationOf(q);
    EXPECT_EQ(std::abs(o.w), unit.w) << q;
    EXPECT_EQ(std::abs(o.x), unit.x) << q;
    EXPECT_EQ(o.y, 0.0) << q;
    EXPECT_EQ(o.z, 0.0) << q;
  }
  const std::string zero = dir + "/zero.csv";
  test::writeBytes(zero, "t,x,y,z,drill_on,qw,qx,qy,qz\n0,0,0,0,1,1,0,0,0\n1,0,0,0,1,0,0,0,0\n");
  try {
    loadPathCsv(zero);
    ADD_FAILURE() << "accepted a zero quaternion";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(zero + ":3:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("zero"), std::string::npos) << e.what();
  }
}

TEST(PathCsv, AcceptsAUtf8ByteOrderMark) {
  const std::string dir = test::makeTempDir("path_csv_bom");
  const std::string file = dir + "/bom.csv";
  test::writeBytes(file, "\xEF\xBB\xBFt,x,y,z,drill_on\n0,0,0,0,1\n1,0,0,1,1\n");
  EXPECT_EQ(loadPathCsv(file).points().size(), 2u);
  // Only at the start of the file: elsewhere it is not part of a number.
  test::writeBytes(file,
                   "t,x,y,z,drill_on\n0,0,0,0,1\n\xEF\xBB\xBF"
                   "1,0,0,1,1\n");
  EXPECT_THROW(loadPathCsv(file), InputError);
}

}  // namespace
}  // namespace osteon::simulation
