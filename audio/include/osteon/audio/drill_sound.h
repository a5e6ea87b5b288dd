// The drill's sound, synthesised from what the simulation knows at each 1 kHz step: the motor's
// speed, the bone removed per second and the load on the tool (docs/feel.md, "Sound").
// - The motor: a tone at its output speed, rpm/60 Hz, with harmonics 2..6, and a whine at the
//   gear's multiple (kGearRatio x rpm/60: the motor spins that much faster than the bit), so
//   that a 1000 rpm drill, whose 16.7 Hz line alone no speaker renders, is heard.
// - Cutting: noise through a band-pass whose level follows the removal rate and whose centre,
//   like the motor's tones, drops with load (the motor slows: rpm x (1 - kSlowdownPerN x load)).
// - Idle and engaged voices of the motor cross-fade with contact, as CardinalSim's samples do.
// Every parameter glides to its target (one-pole, ~20 ms) and the oscillators keep their
// phase, so nothing clicks. Pure DSP: no allocation, no locks, noise from a fixed seed, so the
// same frames give the same samples.
#pragma once

#include <cstddef>
#include <cstdint>

namespace osteon::audio {

inline constexpr double kSampleRateHz = 44100.0;
inline constexpr double kGearRatio = 24.0;        // motor turns per turn of the bit
inline constexpr double kSlowdownPerN = 0.06;     // fraction of rpm lost per newton of load
inline constexpr double kMinSpeedFraction = 0.5;  // the motor never stalls below half speed
inline constexpr double kFullCutMm3PerS = 8.0;    // removal rate at half the cutting level

// One step's worth of what the sound follows (plain data: it crosses the ring).
struct SoundFrame {
  double tS = 0.0;              // the step's time
  double rpm = 1000.0;          // the drill's set speed (the bit's)
  double removalMm3PerS = 0.0;  // bone removed per second at this step
  double loadN = 0.0;           // the force on the tool (sent to the hand)
  bool drillOn = true;          // the motor runs
};

// The bit's speed under load (rpm): the motor slows as the force rises.
double loadedRpm(double rpm, double loadN) noexcept;

class DrillSound {
 public:
  explicit DrillSound(double sampleRateHz = kSampleRateHz, std::uint64_t noiseSeed = 0x05734e0dULL);

  // The frame the next samples glide towards.
  void setTarget(const SoundFrame& frame) noexcept;
  // 0 mutes (gliding, without a click), 1 is full level.
  void setMasterGain(double gain) noexcept { targetMaster_ = gain; }
  // n samples in [-1, 1] into out.
  void render(float* out, std::size_t n) noexcept;
  double sampleRateHz() const { return rateHz_; }

 private:
  double nextNoise() noexcept;

  double rateHz_;
  double glide_;  // one-pole coefficient per sample
  std::uint64_t noiseState_;
  // targets
  double targetHz_ = 0.0, targetMotor_ = 0.0, targetEngaged_ = 0.0, targetCut_ = 0.0;
  double targetCutHz_ = 3000.0, targetMaster_ = 1.0;
  // smoothed values
  double hz_ = 0.0, motor_ = 0.0, engaged_ = 0.0, cut_ = 0.0, cutHz_ = 3000.0, master_ = 1.0;
  double phase_ = 0.0;            // of the bit's turn, in turns [0, 1)
  double whinePhase_ = 0.0;       // of the motor's
  double bp1_ = 0.0, bp2_ = 0.0;  // the band-pass's state (Chamberlin state-variable filter)
};

}  // namespace osteon::audio
