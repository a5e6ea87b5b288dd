#include "osteon/audio/drill_sound.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace osteon::audio {

namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr double kGlideS = 0.02;         // parameters reach 63 % of a change in 20 ms
constexpr double kContactN = 0.05;       // a load above this is contact (engaged voice)
constexpr double kCutCentreHz = 3000.0;  // the band-pass's centre at full speed
constexpr double kCutQ = 1.5;
constexpr int kHarmonics = 6;  // the bit's line and harmonics 2..6
// The voices' weights: fundamental and harmonics 2..6, then the whine and its octave. Idle is
// bright (the free-running whine), engaged duller and lower (the bit loaded in bone).
constexpr std::array<double, kHarmonics + 2> kIdle = {0.22, 0.11, 0.07, 0.05,
                                                      0.04, 0.03, 0.16, 0.06};
constexpr std::array<double, kHarmonics + 2> kEngaged = {0.30, 0.15, 0.08, 0.04,
                                                         0.03, 0.02, 0.09, 0.02};

double wrap(double turns) {
  return turns - std::floor(turns);
}

}  // namespace

double loadedRpm(double rpm, double loadN) noexcept {
  const double fraction = std::max(kMinSpeedFraction, 1.0 - kSlowdownPerN * std::max(0.0, loadN));
  return std::max(0.0, rpm) * fraction;
}

DrillSound::DrillSound(double sampleRateHz, std::uint64_t noiseSeed)
    : rateHz_(sampleRateHz),
      glide_(1.0 - std::exp(-1.0 / (kGlideS * sampleRateHz))),
      noiseState_(noiseSeed ? noiseSeed : 1) {}

void DrillSound::setTarget(const SoundFrame& f) noexcept {
  const double rpm = std::isfinite(f.rpm) ? f.rpm : 0.0;
  const double load = std::isfinite(f.loadN) ? std::max(0.0, f.loadN) : 0.0;
  const double removal = std::isfinite(f.removalMm3PerS) ? std::max(0.0, f.removalMm3PerS) : 0.0;
  const double turning = loadedRpm(rpm, load);
  // A motor switched off keeps its last pitch while it fades, rather than sweeping down to 0.
  if (f.drillOn && turning > 0.0) targetHz_ = turning / 60.0;
  targetMotor_ = f.drillOn && turning > 0.0 ? 1.0 : 0.0;
  targetEngaged_ = f.drillOn && (load > kContactN || removal > 0.0) ? 1.0 : 0.0;
  targetCut_ = f.drillOn ? removal / (removal + kFullCutMm3PerS) : 0.0;
  targetCutHz_ = kCutCentreHz * (rpm > 0.0 ? turning / rpm : 1.0);
}

double DrillSound::nextNoise() noexcept {
  // xorshift64*: fixed seed, same sequence on every run
  noiseState_ ^= noiseState_ >> 12;
  noiseState_ ^= noiseState_ << 25;
  noiseState_ ^= noiseState_ >> 27;
  const std::uint64_t r = noiseState_ * 0x2545F4914F6CDD1DULL;
  return static_cast<double>(r >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

void DrillSound::render(float* out, std::size_t n) noexcept {
  // Morris et al. 2004 and FIVRS pitch the drill's sound by speed and |F|; parameters glide
  // per sample and phases run on so that a changed target never clicks.
  if (hz_ == 0.0) hz_ = targetHz_;  // the first tone starts at its pitch, fading in
  for (std::size_t i = 0; i < n; ++i) {
    hz_ += glide_ * (targetHz_ - hz_);
    motor_ += glide_ * (targetMotor_ - motor_);
    engaged_ += glide_ * (targetEngaged_ - engaged_);
    cut_ += glide_ * (targetCut_ - cut_);
    cutHz_ += glide_ * (targetCutHz_ - cutHz_);
    master_ += glide_ * (targetMaster_ - master_);
    phase_ = wrap(phase_ + hz_ / rateHz_);
    whinePhase_ = wrap(whinePhase_ + hz_ * kGearRatio / rateHz_);

    double motor = 0.0;
    for (int k = 0; k < kHarmonics + 2; ++k) {
      const double angle =
          k < kHarmonics ? kTwoPi * phase_ * (k + 1) : kTwoPi * whinePhase_ * (k - kHarmonics + 1);
      const auto idx = static_cast<std::size_t>(k);
      motor += ((1.0 - engaged_) * kIdle[idx] + engaged_ * kEngaged[idx]) * std::sin(angle);
    }
    // Chamberlin's state-variable band-pass, its centre held below a sixth of the rate.
    const double centre = std::clamp(cutHz_, 200.0, rateHz_ / 6.0);
    const double f = 2.0 * std::sin(kTwoPi * centre / (2.0 * rateHz_));
    bp2_ += f * bp1_;  // low-pass
    const double high = nextNoise() - bp2_ - bp1_ / kCutQ;
    bp1_ += f * high;  // band-pass
    const double sample = master_ * (motor_ * motor + cut_ * 0.7 * bp1_);
    out[i] = static_cast<float>(std::clamp(sample, -1.0, 1.0));
  }
}

}  // namespace osteon::audio
