// The drill's sound in the viewer under Xvfb: without an audio device it runs silent and says
// so once; --mute starts muted; with a device (OpenAL Soft's wave writer standing in for a sound
// card) the frames reach the audio thread, none dropped, and sound is written. A toggles it.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "viewer/viewer_hand.h"

namespace osteon {
namespace {

using ViewerSoundTest = test::ViewerHand;
using nlohmann::json;

std::size_t countOf(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
    ++n;
  return n;
}

TEST_F(ViewerSoundTest, WithoutADeviceItRunsSilentAndSaysSoOnce) {
  for (const char* mute : {"", " --mute"}) {
    // No backend OpenAL Soft knows: no device, as on a machine without a sound card.
    setenv("ALSOFT_DRIVERS", "none-such", 1);
    const test::ProcessRun r =
        run("default --voxel-size 1.2 --path portal-5 --frames 30 "
            "--size 640x480 --json" +
            std::string(mute));
    unsetenv("ALSOFT_DRIVERS");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(countOf(r.err, "running without sound"), 1u) << r.err;
    const json j = json::parse(r.out)["sound"];
    EXPECT_FALSE(j["device"].get<bool>());
    EXPECT_EQ(j["muted"].get<bool>(), *mute != '\0');
    EXPECT_GT(j["frames"].get<std::uint64_t>(), 0u);
    EXPECT_EQ(j["dropped"].get<std::uint64_t>(), 0u);
  }
}

TEST_F(ViewerSoundTest, WithADeviceFramesReachTheAudioThread) {
  const std::string conf = path("alsoft.conf"), wav = path("device.wav");
  std::ofstream(conf) << "[general]\ndrivers=wave\n[wave]\nfile=" << wav << "\n";
  setenv("ALSOFT_CONF", conf.c_str(), 1);
  const test::ProcessRun r =
      run("default --voxel-size 1.2 --path portal-5 --frames 60 --size 640x480 --json");
  unsetenv("ALSOFT_CONF");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.err.find("without sound"), std::string::npos) << r.err;
  const json j = json::parse(r.out)["sound"];
  EXPECT_TRUE(j["device"].get<bool>());
  EXPECT_FALSE(j["muted"].get<bool>());
  EXPECT_GE(j["frames"].get<std::uint64_t>(), 60u);
  EXPECT_EQ(j["dropped"].get<std::uint64_t>(), 0u);
  ASSERT_TRUE(std::filesystem::exists(wav));
  EXPECT_GT(std::filesystem::file_size(wav), 44100u);  // a fraction of a second, at least
}

TEST_F(ViewerSoundTest, AMutesAndUnmutes) {
  const json once = hand("", "xdotool key a; sleep 0.5\n", "viewer_sound_a.png");
  ASSERT_FALSE(once.empty());
  EXPECT_TRUE(once["sound"]["muted"].get<bool>());
  const json twice = hand(
      "--mute", "xdotool key a; sleep 0.3; xdotool key a; sleep 0.3; xdotool key a; sleep 0.5\n",
      "viewer_sound_aaa.png");
  ASSERT_FALSE(twice.empty());
  EXPECT_FALSE(twice["sound"]["muted"].get<bool>());
}

}  // namespace
}  // namespace osteon
