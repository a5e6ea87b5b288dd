// The summary reports the refinement the step's budget deferred: a jump of the tool 12 mm
// along portal 5 in one step, straight into bone (direct coupling: the tool where the path
// puts it), meets more bone around its parts than one step refines, so the rest goes to the
// next steps and the summary counts them (refine_steps_deferred, refine_voxels_deferred),
// beside max_gap_mm and clamp_steps. Under proxy coupling the bone stops the tool instead.
#include <cmath>
#include <sstream>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "support/cli_fixture.h"
#include "support/files.h"

namespace osteon {
namespace {

using nlohmann::json;

glm::dvec3 vec(const json& j) {
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

// From 6 mm before the entry to 6 mm past it along the portal's direction in 1 ms at 0.5 s,
// then held to 2 s; the drill on, the tool pointing along the direction throughout.
std::string jumpCsv(const glm::dvec3& entryMm, const glm::dvec3& directionIn) {
  const glm::dvec3 d = glm::normalize(directionIn);
  // The tool's -z onto d by the shortest arc (as ToolPose::pointing).
  const glm::dvec3 from(0.0, 0.0, -1.0), axis = glm::cross(from, d);
  const double c = glm::dot(from, d);
  const double qn = std::sqrt((1.0 + c) * (1.0 + c) + glm::dot(axis, axis));
  std::ostringstream s;
  s.precision(9);
  s << "t,x,y,z,drill_on,qw,qx,qy,qz\n";
  for (const auto& [t, alongMm] : {std::pair{0.0, -6.0}, {0.5, -6.0}, {0.501, 6.0}, {2.0, 6.0}}) {
    const glm::dvec3 p = entryMm + alongMm * d;
    s << t << "," << p.x << "," << p.y << "," << p.z << ",1," << (1.0 + c) / qn << ","
      << axis.x / qn << "," << axis.y / qn << "," << axis.z / qn << "\n";
  }
  return s.str();
}

TEST_F(CliTest, TheSummaryCountsTheRefinementTheStepBudgetDeferred) {
  const std::string common = " --voxel-size 1.2 --levels 2 --json --out-dir ";
  const CliRun portal =
      osteon("drill default --path portal-5" + common + "'" + path("portal") + "'");
  ASSERT_EQ(portal.exitCode, 0) << portal.err;
  const json p = json::parse(portal.out);
  // The seed's path meets bone gradually: nothing deferred, and the fields are there.
  EXPECT_EQ(p["refine_steps_deferred"].get<std::uint64_t>(), 0u);
  EXPECT_EQ(p["refine_voxels_deferred"].get<std::uint64_t>(), 0u);
  EXPECT_FALSE(p["degraded"].get<bool>());  // no counter of runner.h moved

  test::writeBytes(path("jump.csv"),
                   jumpCsv(vec(p["path"]["entry_mm"]), vec(p["path"]["direction"])));
  const CliRun direct = osteon("drill default --coupling direct --path '" + path("jump.csv") + "'" +
                               common + "'" + path("direct") + "'");
  ASSERT_EQ(direct.exitCode, 0) << direct.err;
  const json d = json::parse(direct.out);
  const auto steps = d["refine_steps_deferred"].get<std::uint64_t>();
  const auto voxels = d["refine_voxels_deferred"].get<std::uint64_t>();
  EXPECT_GT(steps, 0u);
  EXPECT_GE(voxels, steps);  // each deferring step left at least one voxel
  EXPECT_EQ(d["max_gap_mm"].get<double>(), 0.0);
  // summary.json says what --json says.
  const json file = json::parse(test::readBytes(path("direct/summary.json")));
  EXPECT_EQ(file["refine_steps_deferred"].get<std::uint64_t>(), steps);
  EXPECT_EQ(file["refine_voxels_deferred"].get<std::uint64_t>(), voxels);
  EXPECT_TRUE(file["degraded"].get<bool>());  // the deferrals made it so

  // Under proxy coupling the bone stops the jump: the gap opens, the force goes to the clamp.
  const CliRun proxy = osteon("drill default --coupling proxy --path '" + path("jump.csv") + "'" +
                              common + "'" + path("proxy") + "'");
  ASSERT_EQ(proxy.exitCode, 0) << proxy.err;
  const json x = json::parse(proxy.out);
  EXPECT_GT(x["max_gap_mm"].get<double>(), 5.0);
  EXPECT_GT(x["clamp_steps"].get<std::uint64_t>(), 0u);
  EXPECT_TRUE(x.contains("refine_steps_deferred"));
  EXPECT_TRUE(x.contains("refine_voxels_deferred"));
}

}  // namespace
}  // namespace osteon
