// The window's keys as a trainee presses them (xdotool under Xvfb): Esc asks before quitting,
// F1 shows and hides the key help, Backspace resets the bone, V and P switch the cameras and
// the picture-in-picture, , and . turn the arthroscope's lens.
#include <string>

#include "viewer/viewer_hand.h"

namespace osteon {
namespace {

using ViewerKeysTest = test::ViewerHand;
using nlohmann::json;

// Esc alone does not quit: the viewer is still running a second later, and Esc again closes
// the question. The fixture then quits with Esc and Enter.
TEST_F(ViewerKeysTest, EscAsksBeforeQuitting) {
  const json j = hand("",
                      "xdotool key Escape; sleep 1; kill -0 $pid || exit 98\n"
                      "xdotool key Escape; sleep 0.5\n",
                      "viewer_keys_esc.png");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["bones_loaded"].get<std::size_t>(), 1u);
}

// F1 shows the help and F1 hides it: were it still shown, the fixture's Esc would only close
// it and the viewer would not quit.
TEST_F(ViewerKeysTest, F1ShowsTheKeysAndF1HidesThem) {
  const json j =
      hand("", "xdotool key F1; sleep 1; xdotool key F1; sleep 0.5\n", "viewer_keys_help.png");
  ASSERT_FALSE(j.empty());
  EXPECT_FALSE(j["help"].get<bool>());
  EXPECT_GT(j["help_frames"].get<std::uint64_t>(), 0u);
}

// ? shows it too, and Esc closes the help before it would ask to quit.
TEST_F(ViewerKeysTest, QuestionMarkShowsTheKeysAndEscClosesThem) {
  const json j = hand("", "xdotool key question; sleep 1; xdotool key Escape; sleep 0.5\n",
                      "viewer_keys_help_question.png");
  ASSERT_FALSE(j.empty());
  EXPECT_FALSE(j["help"].get<bool>());
  EXPECT_GT(j["help_frames"].get<std::uint64_t>(), 0u);
}

// A hole drilled, then Backspace: the bone is loaded again as it was, nothing removed from it.
TEST_F(ViewerKeysTest, BackspaceResetsTheBone) {
  const std::string drill =
      "xdotool keydown shift click --repeat 60 --delay 20 4 keyup shift; sleep 1\n"
      "xdotool key space; sleep 3; xdotool key space; sleep 0.5\n";
  const json drilled = hand("--focus tool --zoom 4", drill, "viewer_keys_drilled.png");
  ASSERT_FALSE(drilled.empty());
  EXPECT_GT(drilled["removed_volume_mm3"].get<double>(), 5.0);
  const json reset = hand("--focus tool --zoom 4", drill + "xdotool key BackSpace; sleep 8\n",
                          "viewer_keys_reset.png");
  ASSERT_FALSE(reset.empty());
  EXPECT_EQ(reset["bones_loaded"].get<std::size_t>(), 2u);
  EXPECT_EQ(reset["removed_volume_mm3"].get<double>(), 0.0);
  EXPECT_EQ(reset["surface"]["components"].get<std::size_t>(), 1u);
}

// V: orbit, arthroscope, follow; P the picture-in-picture; . turns the lens 15 degrees a press.
TEST_F(ViewerKeysTest, CameraKeysSwitchTheViewAndTurnTheLens) {
  const json j = hand("",
                      "xdotool key v; sleep 0.3; xdotool key p; sleep 0.3\n"
                      "xdotool key period period period comma; sleep 0.5\n",
                      "viewer_keys_scope.png");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["camera"], "scope");
  EXPECT_TRUE(j["picture_in_picture"].get<bool>());
  EXPECT_NEAR(j["lens_rotation_deg"].get<double>(), 30.0, 1e-9);
}

// An exercise by hand: E ends the trial and scores it (the loops stop, the window goes on),
// Backspace loads the exercise again for another trial, which is scored at exit.
TEST_F(ViewerKeysTest, EEndsTheTrialAndBackspaceStartsAnother) {
  const json scored =
      hand("", "xdotool key e; sleep 2\n", "viewer_keys_scored.png", "--exercise anchor-5");
  ASSERT_FALSE(scored.empty());
  EXPECT_EQ(scored["exercise"], "anchor-5");
  ASSERT_TRUE(scored["score"].is_object());
  EXPECT_FALSE(scored["score"]["passed"].get<bool>());  // nothing was drilled
  const json again = hand("", "xdotool key e; sleep 1; xdotool key BackSpace; sleep 8\n",
                          "viewer_keys_again.png", "--exercise anchor-5");
  ASSERT_FALSE(again.empty());
  EXPECT_EQ(again["bones_loaded"].get<std::size_t>(), 2u);
  EXPECT_EQ(again["exercise"], "anchor-5");
  EXPECT_TRUE(again["score"].is_object());
}

}  // namespace
}  // namespace osteon
