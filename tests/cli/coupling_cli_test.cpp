// --coupling proxy|direct as users meet it: a path that pushes 10 mm past the bone's surface
// with the drill off for 5 s, then drills for 2 s. Under proxy coupling (the default for a CSV
// path) bone stops the tool, the drill opens a hole from the surface (one surface component,
// no sealed cavity), forces.csv gains the commanded tip and the summary the largest gap and
// the steps at the clamp. Portal paths keep direct coupling and their columns.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/simulation/motions.h"
#include "support/cli_fixture.h"
#include "support/files.h"

namespace osteon {
namespace {

using nlohmann::json;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

std::string firstLine(const std::string& text) {
  return text.substr(0, text.find('\n'));
}

// The push path the coupling tests and the drilling bench drive (simulation::intactPushPath)
// at portal 5's entry on the built-in humerus (`default`): from 6 mm outside to the tip's
// centre 10 mm inside along the inward normal in 1 s, held there, the drill on from 5 s to 7 s.
std::string pushCsv() {
  const geometry::HumerusModel model = geometry::buildHumerusModel();
  const simulation::PortalPlan plan = simulation::makePortalPath(
      simulation::Portal::FiveOClock, simulation::fitHumeralHead(model.mesh), model.mesh, 1.5);
  std::ostringstream s;
  s.precision(17);
  s << "t,x,y,z,drill_on,qw,qx,qy,qz\n";
  const simulation::DrillPath push = simulation::intactPushPath(plan);
  for (const simulation::Waypoint& w : push.points()) {
    s << w.tS << "," << w.tipMm.x << "," << w.tipMm.y << "," << w.tipMm.z << ","
      << (w.drillOn ? 1 : 0) << "," << w.orientation.w << "," << w.orientation.x << ","
      << w.orientation.y << "," << w.orientation.z << "\n";
  }
  return s.str();
}

TEST_F(CliTest, AProxyThatBoneStopsDrillsAHoleFromTheSurface) {
  const std::string common = " --voxel-size 1.2 --levels 2 --json --out-dir ";
  const CliRun portal = osteon("drill default --path portal-5" + common + quoted(path("portal")));
  ASSERT_EQ(portal.exitCode, 0) << portal.err;
  const json p = json::parse(portal.out);
  EXPECT_EQ(p["coupling"], "direct");  // portal paths: the seed's experiment, as it was
  EXPECT_EQ(p["max_gap_mm"].get<double>(), 0.0);
  EXPECT_EQ(firstLine(test::readBytes(path("portal/forces.csv"))),
            "t,px,py,pz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level");

  test::writeBytes(path("push.csv"), pushCsv());
  const CliRun proxy =
      osteon("drill default --path " + quoted(path("push.csv")) + common + quoted(path("proxy")));
  ASSERT_EQ(proxy.exitCode, 0) << proxy.err;
  const json j = json::parse(proxy.out);
  EXPECT_EQ(j["coupling"], "proxy");
  // The command ends 10 mm past the surface; the proxy stays near it, then drills in.
  EXPECT_GT(j["max_gap_mm"].get<double>(), 8.0);
  EXPECT_GT(j["clamp_steps"].get<std::uint64_t>(), 0u);
  EXPECT_LE(j["max_force_n"].get<double>(), 3.3);
  EXPECT_GT(j["removed_volume_mm3"].get<double>(), 1.0);
  EXPECT_LT(j["max_step_change_n"].get<double>(), 0.1);
  const std::string log = test::readBytes(path("proxy/forces.csv"));
  EXPECT_EQ(firstLine(log),
            "t,px,py,pz,cx,cy,cz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level");
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 7002);
  const geometry::MeshTopology topology =
      geometry::analyzeTopology(geometry::readMesh(path("proxy/surface.ply")));
  EXPECT_EQ(topology.components, 1u);  // a hole from the surface: no sealed cavity
  EXPECT_EQ(topology.borderEdges, 0u);

  // The same path with --coupling direct: the tool goes where the path puts it.
  const CliRun direct = osteon("drill default --coupling direct --path " +
                               quoted(path("push.csv")) + common + quoted(path("direct")));
  ASSERT_EQ(direct.exitCode, 0) << direct.err;
  const json d = json::parse(direct.out);
  EXPECT_EQ(d["coupling"], "direct");
  EXPECT_EQ(firstLine(test::readBytes(path("direct/forces.csv"))),
            "t,px,py,pz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level");
  std::printf(
      "push, proxy: max 1 ms step %.4f N, largest gap %.3f mm, %llu steps at the clamp, removed "
      "%.2f mm3; "
      "direct: max 1 ms step %.4f N, %llu steps at the clamp, %zu surface components\n",
      j["max_step_change_n"].get<double>(), j["max_gap_mm"].get<double>(),
      (unsigned long long)j["clamp_steps"].get<std::uint64_t>(),
      j["removed_volume_mm3"].get<double>(), d["max_step_change_n"].get<double>(),
      (unsigned long long)d["clamp_steps"].get<std::uint64_t>(),
      geometry::analyzeTopology(geometry::readMesh(path("direct/surface.ply"))).components);
}

// A device (the push path, scripted) and its recording replayed run under proxy coupling by
// default: the force the coupling asks for goes through the safety layer, which limits it
// again, and the replay gives the device run's force log byte for byte.
TEST_F(CliTest, DevicesAndReplaysRunThroughTheProxyThenTheSafetyLayer) {
  const std::string common = " --voxel-size 1.2 --levels 2 --json --out-dir ";
  test::writeBytes(path("push.csv"), pushCsv());

  const CliRun device =
      osteon("drill default --device scripted:" + quoted(path("push.csv")) + " --record " +
             quoted(path("rec.csv")) + common + quoted(path("device")));
  ASSERT_EQ(device.exitCode, 0) << device.err;
  const json d = json::parse(device.out);
  EXPECT_EQ(d["coupling"], "proxy");
  EXPECT_GT(d["max_gap_mm"].get<double>(), 8.0);
  EXPECT_GT(d["clamp_steps"].get<std::uint64_t>(), 0u);
  // What the device was sent: within the safety layer's limit, and it did send the push back.
  EXPECT_LE(d["safety"]["max_force_n"].get<double>(),
            d["safety"]["force_limit_n"].get<double>() + 1e-9);
  EXPECT_GT(d["safety"]["max_force_n"].get<double>(), 3.0);
  EXPECT_EQ(d["safety"]["non_finite_forces"].get<std::uint64_t>(), 0u);
  const std::string log = test::readBytes(path("device/forces.csv"));
  EXPECT_EQ(firstLine(log),
            "t,px,py,pz,cx,cy,cz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level");

  const CliRun replay =
      osteon("replay " + quoted(path("rec.csv")) + " default" + common + quoted(path("replay")));
  ASSERT_EQ(replay.exitCode, 0) << replay.err;
  EXPECT_EQ(json::parse(replay.out)["coupling"], "proxy");
  EXPECT_TRUE(log == test::readBytes(path("replay/forces.csv")));
}

TEST_F(CliTest, AnUnknownCouplingIsRefused) {
  expectBadInput("drill default --voxel-size 1.2 --path portal-5 --coupling spring --out-dir " +
                     quoted(path("o")),
                 "--coupling spring", "unknown coupling");
  test::writeBytes(path("log.csv"),
                   "t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on\n0,0,0,0,1,0,0,0,0,0,0\n");
  expectBadInput("replay " + quoted(path("log.csv")) +
                     " default --voxel-size 1.2 --coupling Proxy --out-dir " + quoted(path("o")),
                 "--coupling Proxy", "unknown coupling");
  EXPECT_FALSE(std::filesystem::exists(path("o/forces.csv")));
}

}  // namespace
}  // namespace osteon
