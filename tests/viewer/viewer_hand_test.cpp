// osteon-viewer driven as a trainee drives it: real X input (xdotool's XTEST events) to the
// window under Xvfb, the mouse tool pushed into the humeral head with Shift + wheel, the drill
// switched with Space, the window closed with Esc; what happened read from --json and the
// last frame written with --screenshot. Skipped, with the reason, when Xvfb or xdotool is
// missing (scripts/setup installs both).
//
// Set OSTEON_VIEWER_SHOTS=DIR to keep the screenshots (they show the ghost inside the bone with
// the proxy at the surface, and the hole drilled from the surface).
#include "viewer/viewer_hand.h"

#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/shapes.h"

namespace osteon {
namespace {

using nlohmann::json;

// Shift + wheel up advances the mouse tool 0.25 mm a notch along its own axis: 60 notches
// command 15 mm, from the resting pose (about 2.5 mm off the head) to 12 mm into it.
const std::string kPush =
    "xdotool keydown shift click --repeat 60 --delay 20 4 keyup shift; sleep 2\n";
// The drill on for 3 s (the proxy feeds in at most 5 mm/s), off, the hand backed out 20 mm
// and the tool hidden (G), so the last frame shows the hole.
const std::string kDrillAndBackOut =
    "xdotool key space; sleep 3; xdotool key space\n"
    "xdotool keydown shift click --repeat 80 --delay 10 5 keyup shift\n"
    "sleep 1.5; xdotool key g; sleep 0.5\n";

using ViewerHandTest = test::ViewerHand;

// The mouse tool cannot be pushed into intact bone: the hand goes 12 mm in, the proxy stays
// at the surface within its cushion, nothing is removed; the commanded pose shows as a ghost.
TEST_F(ViewerHandTest, TheMouseToolIsStoppedByIntactBone) {
  const json j = hand("--focus tool --zoom 4", kPush, "viewer_proxy_ghost.png");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["coupling"], "proxy");  // the mouse's default
  EXPECT_EQ(j["removed_volume_mm3"].get<double>(), 0.0);
  EXPECT_GT(j["max_gap_mm"].get<double>(), 8.0);
  EXPECT_GT(j["depth_in_bone_mm"]["commanded"].get<double>(), 8.0);
  EXPECT_LE(j["depth_in_bone_mm"]["proxy"].get<double>(), j["tool_cushion_mm"].get<double>());
  EXPECT_GT(j["clamp_steps"].get<std::uint64_t>(), 0u);
  EXPECT_LE(j["max_force_n"].get<double>(), 3.3);
  // Held there at the end: the ghost is drawn.
  EXPECT_TRUE(j["ghost"].get<bool>());
  EXPECT_GT(j["gap_mm"].get<double>(), 8.0);
  EXPECT_EQ(j["surface"]["components"].get<std::size_t>(), 1u);
}

// Then the drill on: it eats its way in from the surface, and the hole opens from the surface:
// one surface component, no sealed cavity. (How deep the proxy sits is not checked here: in a
// hole, level-0 voxels half full at its wall stand for sub-voxels the drill has already cut.)
TEST_F(ViewerHandTest, DrillingOpensAHoleFromTheSurface) {
  const json j = hand("--camera left --focus tool --zoom 5", kPush + kDrillAndBackOut,
                      "viewer_proxy_hole.png");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["coupling"], "proxy");
  EXPECT_GT(j["max_gap_mm"].get<double>(), 8.0);
  EXPECT_GT(j["removed_volume_mm3"].get<double>(), 10.0);
  EXPECT_LE(j["max_force_n"].get<double>(), 3.3);
  EXPECT_EQ(j["surface"]["components"].get<std::size_t>(), 1u);
  EXPECT_EQ(j["surface"]["border_edges"].get<std::size_t>(), 0u);
}

// The same hand under --coupling direct, the seed's: the tool goes where it is pushed, 8 mm
// and more into the bone, and the drill there carves a cavity the surface does not reach.
TEST_F(ViewerHandTest, UnderDirectCouplingTheSameHandPassesThroughTheBone) {
  const json j = hand("--coupling direct --camera left --focus tool --zoom 5",
                      kPush + kDrillAndBackOut, "viewer_direct_cavity.png");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["coupling"], "direct");
  EXPECT_EQ(j["ghost_frames"].get<std::uint64_t>(), 0u);
  EXPECT_GT(j["depth_in_bone_mm"]["proxy"].get<double>(), 8.0);
  EXPECT_GT(j["removed_volume_mm3"].get<double>(), 10.0);
  EXPECT_GT(j["surface"]["components"].get<std::size_t>(), 1u);
}

}  // namespace
}  // namespace osteon
