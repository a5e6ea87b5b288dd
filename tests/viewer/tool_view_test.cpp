// What the viewer draws of the tool under proxy coupling, without a window: when the commanded
// pose's ghost joins the proxy, and how deep a pose sits in bone (viewer/src/tool_view.h).
#include "tool_view.h"

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

namespace osteon::viewer {
namespace {

namespace sim = osteon::simulation;

sim::Tool drill() {
  return sim::makeTool(sim::ToolKind::Drill, {}, 0.3);
}

// 40 mm cube of 1 mm voxels, bone (full) below z = 20 mm.
geometry::VoxelGrid halfSpace() {
  geometry::VoxelGrid grid({40, 40, 40}, glm::dvec3(0.0), 1.0);
  for (int z = 0; z < 20; ++z) {
    for (int y = 0; y < 40; ++y) {
      for (int x = 0; x < 40; ++x) grid.set({x, y, z}, geometry::kFillFull, 1);
    }
  }
  return grid;
}

sim::ToolPose downAt(double zMm) {
  return sim::ToolPose::pointing({20.5, 20.5, zMm}, {0.0, 0.0, -1.0});
}

TEST(ToolView, TheGhostShowsWhenAnyPartOfTheCommandedPoseIsAHairAway) {
  const sim::Tool tool = drill();
  const sim::ToolPose proxy = downAt(25.0);
  EXPECT_EQ(toolOffsetMm(tool, proxy, proxy), 0.0);
  EXPECT_FALSE(showGhost(tool, proxy, proxy));
  sim::ToolPose near = proxy;
  near.tipMm.z -= 0.03;
  EXPECT_NEAR(toolOffsetMm(tool, proxy, near), 0.03, 1e-12);
  EXPECT_FALSE(showGhost(tool, proxy, near));
  sim::ToolPose pushed = proxy;
  pushed.tipMm.z -= 10.0;
  EXPECT_TRUE(showGhost(tool, proxy, pushed));
  // Turned about the tip by 0.01 rad: the tip stays, the shaft's far end moves its distance
  // from the tip times 0.01, and that is what shows.
  sim::ToolPose turned = proxy;
  turned.orientation = glm::angleAxis(0.01, glm::dvec3(1.0, 0.0, 0.0)) * proxy.orientation;
  const sim::ToolPart& shaft = tool.parts[1];
  EXPECT_NEAR(toolOffsetMm(tool, proxy, turned), 2.0 * shaft.bMm.z * std::sin(0.005), 1e-9);
  EXPECT_TRUE(showGhost(tool, proxy, turned));
}

TEST(ToolView, DepthInBoneIsHowFarTheToolMustBackOutAlongItsAxis) {
  const geometry::VoxelGrid grid = halfSpace();
  const sim::Tool tool = drill();
  const double r = tool.parts[0].innerRadiusMm;
  // In the air and just clear of the top voxels' centres (z = 19.5): nothing.
  EXPECT_EQ(boneDepthMm(grid, tool, downAt(30.0)), 0.0);
  EXPECT_EQ(boneDepthMm(grid, tool, downAt(19.5 + r + 1e-6)), 0.0);
  // 5 mm into the bone: the shaft (from ri behind the tip) must rise until its front cap clears
  // the top voxels' centres; the tip sphere, on its own, only the voxel over its centre.
  const sim::ToolPart& shaft = tool.parts[1];
  EXPECT_NEAR(boneDepthMm(grid, tool, downAt(15.0)),
              shaft.innerRadiusMm + 19.5 - (15.0 + shaft.aMm.z), 1e-9);
  // Lying on its side in the bone, 3 mm down: the shaft must come out the length it is in.
  const sim::ToolPose side = sim::ToolPose::pointing({5.5, 20.5, 17.0}, {-1.0, 0.0, 0.0});
  EXPECT_GT(boneDepthMm(grid, tool, side), 20.0);

  // A hole drilled wider than the tip down to z = 10: the same pose sits in no bone.
  geometry::VoxelGrid drilled = grid;
  for (int z = 10; z < 20; ++z) {
    for (int y = 17; y < 24; ++y) {
      for (int x = 17; x < 24; ++x) drilled.set({x, y, z}, 0, 0);
    }
  }
  EXPECT_EQ(boneDepthMm(drilled, tool, downAt(15.0)), 0.0);
  // Voxels under half full do not count as bone.
  for (int z = 10; z < 20; ++z) drilled.set({20, 20, z}, geometry::kFillHalf - 1, 1);
  EXPECT_EQ(boneDepthMm(drilled, tool, downAt(15.0)), 0.0);
  drilled.set({20, 20, 15}, geometry::kFillHalf, 1);  // its centre 0.5 mm over the tip's
  EXPECT_NEAR(boneDepthMm(drilled, tool, downAt(15.0)), r + 0.5, 1e-9);
}

TEST(ToolView, TheTallyCountsGhostFramesAndKeepsTheDeepest) {
  const geometry::VoxelGrid grid = halfSpace();
  const sim::Tool tool = drill();
  const double r = tool.parts[0].innerRadiusMm;
  ASSERT_EQ(tool.partCount, 2);  // tip and shaft
  ToolViewTally tally;
  tally.add(tool, downAt(25.0), downAt(25.0), 0.0, &grid);  // in the air
  EXPECT_FALSE(tally.ghostLast);
  tally.add(tool, downAt(19.5 + r), downAt(12.0), 7.5 + r,
            &grid);  // stopped at the surface, the hand in
  tally.add(tool, downAt(19.5 + r), downAt(15.0), 4.5 + r, &grid);
  EXPECT_TRUE(tally.ghostLast);
  EXPECT_EQ(tally.ghostFrames, 2u);
  EXPECT_EQ(tally.gapLastMm, 4.5 + r);
  EXPECT_EQ(tally.maxProxyDepthMm, 0.0);
  const sim::ToolPart& shaft = tool.parts[1];
  EXPECT_NEAR(tally.maxCommandedDepthMm, shaft.innerRadiusMm + 19.5 - (12.0 + shaft.aMm.z), 1e-9);
  // Without a grid the depths are left as they are.
  tally.add(tool, downAt(5.0), downAt(5.0), 0.0, nullptr);
  EXPECT_EQ(tally.maxProxyDepthMm, 0.0);
  EXPECT_FALSE(tally.ghostLast);
  EXPECT_EQ(tally.ghostFrames, 2u);
}

}  // namespace
}  // namespace osteon::viewer
