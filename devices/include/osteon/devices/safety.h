// The safety layer between any device and the force it is sent, and between any pose stream
// and the session. It must never hurt a hand and never lose a session:
//   force   clamped to the device's limit (3.3 N for the Touch); engaged only once the device
//           has given a pose and the force asked for is below 0.2 N, then ramped in over
//           0.5 s; on a fault ramped out at no more than 0.1 N per 1 ms step (about 35 ms from
//           the 3.3 N cap) to zero, then engaged again through the ramp once the fault has
//           passed (whatever the force then: the 0.2 N rule is for the first engagement);
//   poses   a fault is a non-finite pose, a gap over 5 ms in the stream, a jump over 10 mm in
//           1 ms, or the haptic loop missing its 1 kHz period three times in a row (watchdog);
//           a faulty pose never reaches the session, which holds the last accepted pose.
// Faults are counted by kind (each episode once) and never stop anything.
//
// Each haptic period, from one thread:
//   safety.loopTick(nowS);                              // the watchdog: when this period ran
//   const PoseVerdict& v = safety.acceptPose(nowS, sample);   // what the session may use
//   ... the session's step at v.positionMm, v.orientation ...
//   device.setForce(nowS, safety.limitForce(nowS, contactForceN));
// The per-step functions allocate nothing, lock nothing and throw nothing.
#pragma once

#include <cstdint>

#include "osteon/devices/device.h"

namespace osteon::devices {

struct SafetyOptions {
  double forceLimitN = 3.3;      // the device's limit
  double engageBelowN = 0.2;     // the force asked for must be below this to engage
  double rampInS = 0.5;          // from zero to the full force, once engaged
  double rampOutNPerStep = 0.1;  // the largest fall per step while a fault ramps the force out
  double periodS = 0.001;        // the haptic loop's period (1 kHz)
  double maxGapS = 0.005;        // a pose stream silent longer than this is a gap
  double maxJumpMm = 10.0;       // per period: a pose further from the last accepted is a jump
  int watchdogMisses = 3;        // missed periods in a row that make a watchdog fault
  double missFactor = 1.5;       // a period is missed when the loop's interval passes 1.5 periods
  // After a jump, a stream that stays continuous from the new place for this long is accepted
  // there (the device was moved while unobserved); a one-sample spike is simply dropped.
  double resyncS = 0.05;
};

// Fault kinds, as bits of PoseVerdict::faults.
enum FaultBits : std::uint32_t {
  kFaultNonFinite = 1u << 0,  // NaN or infinite coordinates, or a zero quaternion
  kFaultGap = 1u << 1,        // no new sample for longer than maxGapS
  kFaultJump = 1u << 2,       // moved further than maxJumpMm per period
  kFaultWatchdog = 1u << 3,   // the haptic loop missed its period watchdogMisses times in a row
};

// Episodes of each kind (a fault lasting many steps counts once).
struct FaultCounts {
  std::uint64_t nonFinite = 0;
  std::uint64_t gaps = 0;
  std::uint64_t jumps = 0;
  std::uint64_t watchdog = 0;
  std::uint64_t total() const { return nonFinite + gaps + jumps + watchdog; }
};

struct SafetyStats {
  FaultCounts faults;
  std::uint64_t clampedSteps = 0;     // force asked for above the limit, clamped
  std::uint64_t rampSteps = 0;        // steps ramping in or out
  std::uint64_t heldSteps = 0;        // steps the session got the held pose because of a fault
  std::uint64_t faultSteps = 0;       // steps with any fault active
  std::uint64_t nonFiniteForces = 0;  // force asked for was not finite (sent as a ramp-out)
  std::uint64_t engagements = 0;      // times the force was engaged (ramp-in started)
  double maxForceN = 0.0;             // largest |F| sent
  double maxStepChangeN = 0.0;        // largest |F_i - F_{i-1}| sent
};

// What the session may use this period.
struct PoseVerdict {
  bool valid = false;          // an accepted pose exists (false before the first)
  glm::dvec3 positionMm{0.0};  // the newest accepted pose (held on a fault)
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
  bool drillOn = false;  // off while a fault holds the pose
  std::uint32_t buttons = 0;
  std::uint32_t faults = 0;  // FaultBits active now
};

enum class ForceState : std::uint8_t { Off, RampIn, Engaged, RampOut };

class SafetyLayer {
 public:
  explicit SafetyLayer(const SafetyOptions& options = {});

  // The watchdog: once per haptic period, with the time the period ran.
  void loopTick(double nowS) noexcept;
  // The pose the session may use at nowS, given the device's newest sample.
  const PoseVerdict& acceptPose(double nowS, const DeviceSample& sample) noexcept;
  // The force to send at nowS for the force the simulation asks for (N).
  glm::dvec3 limitForce(double nowS, const glm::dvec3& forceN) noexcept;

  const SafetyOptions& options() const { return options_; }
  const SafetyStats& stats() const { return stats_; }
  const PoseVerdict& verdict() const { return verdict_; }
  ForceState forceState() const { return state_; }

 private:
  void raise(std::uint32_t bit, std::uint32_t wasActive, std::uint64_t& counter) noexcept;
  void accept(const DeviceSample& sample) noexcept;

  SafetyOptions options_;
  SafetyStats stats_;
  PoseVerdict verdict_;
  // watchdog
  double lastTickS_ = 0.0;
  bool ticked_ = false;
  int misses_ = 0;
  bool watchdogActive_ = false;
  // pose stream
  bool seen_ = false;            // any sample seen
  double lastSampleS_ = 0.0;     // newest sample's time
  double acceptedS_ = 0.0;       // accepted pose's sample time
  bool jumping_ = false;         // rejecting a jump, watching the stream settle
  glm::dvec3 candidateMm_{0.0};  // where the stream went
  double candidateS_ = 0.0, candidateSinceS_ = 0.0;
  // force
  ForceState state_ = ForceState::Off;
  double rampStartS_ = 0.0;
  glm::dvec3 lastForceN_{0.0};
};

// Human names of the fault bits, for messages: "non-finite pose", "gap", "jump", "watchdog".
const char* faultName(std::uint32_t bit);

}  // namespace osteon::devices
