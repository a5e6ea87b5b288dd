// The synthesiser alone: the motor's line at rpm/60 Hz and the gear's whine, cutting noise that
// follows the removal rate, a pitch that drops with load, no clicks, the same samples every run.
#include "osteon/audio/drill_sound.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "support/wav_spectrum.h"

namespace osteon::audio {
namespace {

using test::amplitudeAt;
using test::bandLevel;

// `seconds` of sound held at `frame` (after a half second to settle).
std::vector<double> hold(const SoundFrame& frame, double seconds) {
  DrillSound sound;
  sound.setTarget(frame);
  std::vector<float> warm(static_cast<std::size_t>(0.5 * kSampleRateHz));
  sound.render(warm.data(), warm.size());
  std::vector<float> out(static_cast<std::size_t>(seconds * kSampleRateHz));
  sound.render(out.data(), out.size());
  return std::vector<double>(out.begin(), out.end());
}

TEST(DrillSound, MotorLineAtRpmOver60WithTheGearWhine) {
  for (const double rpm : {1000.0, 1500.0}) {
    const std::vector<double> x = hold({0.0, rpm, 0.0, 0.0, true}, 2.0);
    const double f0 = rpm / 60.0;
    const double line = amplitudeAt(x, 0, x.size(), f0, kSampleRateHz);
    EXPECT_GT(line, 0.05) << rpm;
    // Off the line (a third of the way to the next harmonic) there is next to nothing.
    EXPECT_LT(amplitudeAt(x, 0, x.size(), f0 * 1.33, kSampleRateHz), line / 20) << rpm;
    EXPECT_GT(amplitudeAt(x, 0, x.size(), 2 * f0, kSampleRateHz), line / 4) << rpm;
    EXPECT_GT(amplitudeAt(x, 0, x.size(), kGearRatio * f0, kSampleRateHz), line / 4) << rpm;
  }
}

TEST(DrillSound, CuttingBandFollowsTheRemovalRate) {
  const auto cutting = [](double removal) {
    const std::vector<double> x = hold({0.0, 1000.0, removal, 0.0, true}, 1.0);
    return bandLevel(x, 0, x.size(), 2000.0, 4000.0, kSampleRateHz);
  };
  const double none = cutting(0.0), some = cutting(4.0), much = cutting(40.0);
  EXPECT_GT(some, 5 * none);
  EXPECT_GT(much, 1.5 * some);
}

TEST(DrillSound, LoadSlowsTheMotor) {
  EXPECT_DOUBLE_EQ(loadedRpm(1000.0, 0.0), 1000.0);
  EXPECT_LT(loadedRpm(1000.0, 3.0), 1000.0);
  EXPECT_GE(loadedRpm(1000.0, 1e6), kMinSpeedFraction * 1000.0);
  const double loaded = loadedRpm(1500.0, 3.0) / 60.0;
  const std::vector<double> x = hold({0.0, 1500.0, 0.0, 3.0, true}, 2.0);
  EXPECT_GT(amplitudeAt(x, 0, x.size(), loaded, kSampleRateHz),
            5 * amplitudeAt(x, 0, x.size(), 1500.0 / 60.0, kSampleRateHz));
}

TEST(DrillSound, MotorOffIsSilentAndMutingGlides) {
  const std::vector<double> off = hold({0.0, 1000.0, 0.0, 0.0, false}, 0.5);
  double peak = 0.0;
  for (const double s : off) peak = std::max(peak, std::abs(s));
  EXPECT_LT(peak, 1e-3);

  DrillSound sound;
  sound.setTarget({0.0, 1000.0, 0.0, 0.0, true});
  std::vector<float> x(static_cast<std::size_t>(kSampleRateHz));
  sound.render(x.data(), x.size());
  sound.setMasterGain(0.0);
  sound.render(x.data(), x.size());
  EXPECT_LT(std::abs(x.back()), 1e-3);
}

// The largest step between two samples in x (from `last`, the sample before x[0]).
double largestStep(const std::vector<float>& x, float last) {
  double step = 0.0;
  for (const float s : x) {
    step = std::max(step, double(std::abs(s - last)));
    last = s;
  }
  return step;
}

double steadyStep(const SoundFrame& f) {
  DrillSound sound;
  sound.setTarget(f);
  std::vector<float> x(static_cast<std::size_t>(kSampleRateHz / 2));
  sound.render(x.data(), x.size());
  return largestStep(x, x.front());
}

TEST(DrillSound, NoClickWhenTheTargetJumps) {
  // Idle to loaded cutting, to twice the speed, to off: the step between samples as the sound
  // changes stays within what the steady sounds on either side do themselves.
  const std::vector<SoundFrame> frames = {{0.0, 1000.0, 0.0, 0.0, true},
                                          {0.0, 1000.0, 30.0, 3.3, true},
                                          {0.0, 2000.0, 0.0, 0.0, true},
                                          {0.0, 2000.0, 0.0, 0.0, false}};
  DrillSound sound;
  std::vector<float> x(static_cast<std::size_t>(kSampleRateHz / 2));
  sound.setTarget(frames[0]);
  sound.render(x.data(), x.size());
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const float last = x.back();
    sound.setTarget(frames[i]);
    sound.render(x.data(), x.size());
    const double bound = std::max(steadyStep(frames[i - 1]), steadyStep(frames[i]));
    EXPECT_LT(largestStep(x, last), 1.2 * bound) << i;
  }
}

TEST(DrillSound, SameFramesSameSamples) {
  const SoundFrame f{0.0, 1250.0, 12.0, 1.0, true};
  EXPECT_EQ(hold(f, 0.3), hold(f, 0.3));
}

}  // namespace
}  // namespace osteon::audio
