// --audio-out: the drill's sound of a run as a WAV, checked by its spectrum. The motor's line at
// rpm/60 Hz, the cutting band rising on contact and falling once the drill leaves bone; the same
// bytes from drill --path, the scripted device and its replay; bad values refused before the
// run; a failed run leaves no file.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "support/cli_fixture.h"
#include "support/wav_spectrum.h"

namespace osteon {
namespace {

using test::amplitudeAt;
using test::bandLevel;

constexpr double kRateHz = 44100.0;
constexpr double kMotorHz = 1000.0 / 60.0;  // the default 1000 rpm

std::string shellQuoted(const std::string& s) {
  return "'" + s + "'";
}

std::size_t at(double tS) {
  return static_cast<std::size_t>(tS * kRateHz);
}

// The cutting band's level in [t0, t1): the band-pass noise around 3 kHz.
double cutting(const test::WavSamples& w, double t0, double t1) {
  return bandLevel(w.samples, at(t0), at(t1), 2000.0, 4000.0, kRateHz);
}

class AudioCliTest : public CliTest {
 protected:
  const std::string common_ = " --voxel-size 1.2 --levels 2 --out-dir ";
};

TEST_F(AudioCliTest, Portal5HasTheMotorLineAndCutsOnContact) {
  const CliRun run = osteon("drill default --path portal-5" + common_ + shellQuoted(path("run")) +
                            " --audio-out " + shellQuoted(path("portal5.wav")));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const test::WavSamples w = test::readWav(path("portal5.wav"));
  ASSERT_EQ(w.rateHz, 44100u);
  ASSERT_EQ(w.samples.size(), at(7.0));  // the run's 7 s

  // Before contact (the tip meets bone at 0.57 s): the motor's line at rpm/60, nothing halfway
  // to its second harmonic.
  const double line = amplitudeAt(w.samples, at(0.05), at(0.55), kMotorHz, kRateHz);
  EXPECT_GT(line, 0.03);
  EXPECT_LT(amplitudeAt(w.samples, at(0.05), at(0.55), 1.5 * kMotorHz, kRateHz), line / 10);
  // In bone the cutting band is far above its level before contact.
  const double before = cutting(w, 0.05, 0.55), inBone = cutting(w, 2.0, 3.0);
  EXPECT_GT(inBone, 5 * before) << before << " " << inBone;
  // Loaded, the motor slows: the gear's whine moves below its free 400 Hz.
  const double free = amplitudeAt(w.samples, at(2.0), at(3.0), 24 * kMotorHz, kRateHz);
  const double loaded = amplitudeAt(w.samples, at(2.0), at(3.0), 24 * kMotorHz * 0.85, kRateHz);
  EXPECT_GT(loaded, 3 * free) << free << " " << loaded;

  // The same run, the same bytes.
  const CliRun again =
      osteon("drill default --path portal-5" + common_ + shellQuoted(path("again")) +
             " --audio-out " + shellQuoted(path("again.wav")));
  ASSERT_EQ(again.exitCode, 0) << again.err;
  EXPECT_TRUE(test::readBytes(path("portal5.wav")) == test::readBytes(path("again.wav")));
}

TEST_F(AudioCliTest, CuttingFallsWhenTheDrillLeavesBone) {
  // Portal 5's line, in for 3.5 s and back out by 6 s, the drill along it all the way.
  std::ofstream(path("inout.csv"))
      << "t,x,y,z,drill_on,qw,qx,qy,qz\n"
         "0,31.616846,5.935811,24.067886,1,0.4289392,0.1595914,0.8891241,0\n"
         "3.5,24.245722,7.258875,30.175590,1,0.4289392,0.1595914,0.8891241,0\n"
         "6,31.616846,5.935811,24.067886,1,0.4289392,0.1595914,0.8891241,0\n"
         "7,31.616846,5.935811,24.067886,1,0.4289392,0.1595914,0.8891241,0\n";
  const CliRun run =
      osteon("drill default --coupling direct --path " + shellQuoted(path("inout.csv")) + common_ +
             shellQuoted(path("run")) + " --audio-out " + shellQuoted(path("inout.wav")));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const test::WavSamples w = test::readWav(path("inout.wav"));
  ASSERT_EQ(w.samples.size(), at(7.0));
  const double before = cutting(w, 0.05, 0.55), inBone = cutting(w, 2.0, 3.0),
               after = cutting(w, 6.2, 7.0);
  EXPECT_GT(inBone, 5 * before) << before << " " << inBone;
  EXPECT_LT(after, inBone / 5) << inBone << " " << after;
  // Out of the bone the motor runs free again, at rpm/60.
  const double line = amplitudeAt(w.samples, at(6.2), at(7.0), kMotorHz, kRateHz);
  EXPECT_GT(line, 0.03);
}

TEST_F(AudioCliTest, DeviceAndReplaySoundAsThePath) {
  const CliRun drill =
      osteon("drill default --path portal-5" + common_ + shellQuoted(path("drill")) +
             " --audio-out " + shellQuoted(path("drill.wav")));
  ASSERT_EQ(drill.exitCode, 0) << drill.err;
  const CliRun scripted =
      osteon("drill default --device scripted:portal-5 --coupling direct --record " +
             shellQuoted(path("portal5.csv")) + common_ + shellQuoted(path("scripted")) +
             " --audio-out " + shellQuoted(path("scripted.wav")));
  ASSERT_EQ(scripted.exitCode, 0) << scripted.err;
  const CliRun replay =
      osteon("replay " + shellQuoted(path("portal5.csv")) + " default --coupling direct" + common_ +
             shellQuoted(path("replay")) + " --audio-out " + shellQuoted(path("replay.wav")));
  ASSERT_EQ(replay.exitCode, 0) << replay.err;
  const std::string wav = test::readBytes(path("drill.wav"));
  EXPECT_GT(wav.size(), 44u);
  EXPECT_TRUE(wav == test::readBytes(path("scripted.wav")));
  EXPECT_TRUE(wav == test::readBytes(path("replay.wav")));
}

TEST_F(AudioCliTest, BadAudioOutRefusedBeforeTheRun) {
  const std::string run = "drill default --path portal-5" + common_ + shellQuoted(path("run"));
  expectBadInput(run + " --audio-out " + shellQuoted(path("sound.mp3")), "sound.mp3", ".wav");
  expectBadInput(run + " --audio-out " + shellQuoted(path("none/sound.wav")), "none/sound.wav",
                 "cannot write");
  std::filesystem::create_directory(path("folder.wav"));
  expectBadInput(run + " --audio-out " + shellQuoted(path("folder.wav")), "folder.wav",
                 "is a folder");
  EXPECT_FALSE(std::filesystem::exists(path("run/forces.csv")));
}

TEST_F(AudioCliTest, AFailedRunLeavesNoSound) {
  setenv("OSTEON_INJECT_FAULT", "surface-update", 1);
  const CliRun run =
      osteon("drill default --path portal-5 --threaded" + common_ + shellQuoted(path("run")) +
             " --audio-out " + shellQuoted(path("s.wav")));
  unsetenv("OSTEON_INJECT_FAULT");
  EXPECT_EQ(run.exitCode, 3) << run.err;
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find(".wav"), std::string::npos) << entry.path();
  }
}

}  // namespace
}  // namespace osteon
