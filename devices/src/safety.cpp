#include "osteon/devices/safety.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace osteon::devices {

namespace {

// Times compare with a nanosecond of slack: a stream at exactly the limit is not a fault.
constexpr double kSlackS = 1e-9;

bool finitePose(const DeviceSample& s) {
  const glm::dvec3& p = s.positionMm;
  const glm::dquat& q = s.orientation;
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return false;
  if (!(std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)))
    return false;
  return q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z > 1e-12;
}

}  // namespace

const char* faultName(std::uint32_t bit) {
  switch (bit) {
    case kFaultNonFinite:
      return "non-finite pose";
    case kFaultGap:
      return "gap";
    case kFaultJump:
      return "jump";
    case kFaultWatchdog:
      return "watchdog";
    default:
      return "fault";
  }
}

SafetyLayer::SafetyLayer(const SafetyOptions& options) : options_(options) {}

void SafetyLayer::loopTick(double nowS) noexcept {
  if (ticked_) {
    const double interval = nowS - lastTickS_;
    if (interval <= 0.0) return;  // the same period twice
    if (interval > options_.periodS * options_.missFactor) {
      ++misses_;
    } else {
      misses_ = 0;
    }
  }
  ticked_ = true;
  lastTickS_ = nowS;
  if (misses_ >= options_.watchdogMisses) {
    if (!watchdogActive_) ++stats_.faults.watchdog;
    watchdogActive_ = true;
  } else if (misses_ == 0) {
    watchdogActive_ = false;
  }
}

void SafetyLayer::accept(const DeviceSample& s) noexcept {
  verdict_.valid = true;
  verdict_.positionMm = s.positionMm;
  // Unit quaternions pass bit for bit (a replay must reproduce its run exactly).
  const double n2 = glm::dot(s.orientation, s.orientation);
  verdict_.orientation = std::abs(n2 - 1.0) > 1e-9 ? s.orientation / std::sqrt(n2) : s.orientation;
  verdict_.drillOn = s.drillOn;
  verdict_.buttons = s.buttons;
  acceptedS_ = s.tS;
}

void SafetyLayer::raise(std::uint32_t bit, std::uint32_t wasActive,
                        std::uint64_t& counter) noexcept {
  if (!(wasActive & bit)) ++counter;
}

const PoseVerdict& SafetyLayer::acceptPose(double nowS, const DeviceSample& s) noexcept {
  const std::uint32_t was = verdict_.faults;
  std::uint32_t now = watchdogActive_ ? std::uint32_t(kFaultWatchdog) : 0u;
  const double period = options_.periodS;
  bool gapCounted = false;
  if (s.tS >= 0.0) {
    const bool fresh = !seen_ || s.tS > lastSampleS_;
    if (fresh) {
      // The stream fell silent between two samples without a poll noticing (counted once).
      if (seen_ && s.tS - lastSampleS_ > options_.maxGapS + kSlackS) {
        raise(kFaultGap, was, stats_.faults.gaps);
        gapCounted = true;
      }
      if (!finitePose(s)) {
        now |= kFaultNonFinite;
      } else if (!verdict_.valid) {
        accept(s);  // the first pose
        jumping_ = false;
      } else {
        // A hand moves at most maxJumpMm per period: the reach grows with the time since the
        // accepted pose (a gap), but not while a jump is being held (the spike must come back).
        const double sinceAcceptedS = jumping_ ? period : std::max(s.tS - acceptedS_, period);
        const double reachMm = options_.maxJumpMm * sinceAcceptedS / period;
        if (glm::distance(s.positionMm, verdict_.positionMm) <= reachMm) {
          accept(s);
          jumping_ = false;
        } else if (jumping_ &&
                   glm::distance(s.positionMm, candidateMm_) <=
                       options_.maxJumpMm * std::max(s.tS - candidateS_, period) / period) {
          // Continuous from where it jumped: accepted there once it has stayed so long enough.
          candidateMm_ = s.positionMm;
          candidateS_ = s.tS;
          if (s.tS - candidateSinceS_ >= options_.resyncS - kSlackS) {
            accept(s);
            jumping_ = false;
          } else {
            now |= kFaultJump;
          }
        } else {
          if (!jumping_) ++stats_.faults.jumps;
          jumping_ = true;
          candidateMm_ = s.positionMm;
          candidateS_ = candidateSinceS_ = s.tS;
          now |= kFaultJump;
        }
      }
      seen_ = true;
      lastSampleS_ = s.tS;
    } else {
      // The same sample again: its faults stand.
      now |= was & kFaultNonFinite;
      if (jumping_) now |= kFaultJump;
    }
    if (nowS - lastSampleS_ > options_.maxGapS + kSlackS || !s.connected) now |= kFaultGap;
  }
  if (now & kFaultNonFinite) raise(kFaultNonFinite, was, stats_.faults.nonFinite);
  // A gap seen as it happens; one just counted by its spacing is the same episode.
  if ((now & kFaultGap) && !gapCounted) raise(kFaultGap, was, stats_.faults.gaps);
  verdict_.faults = now;
  if (now) ++stats_.faultSteps;
  if (now & (kFaultNonFinite | kFaultGap | kFaultJump)) {
    verdict_.drillOn = false;  // a held tool does not cut
    if (verdict_.valid) ++stats_.heldSteps;
  }
  return verdict_;
}

glm::dvec3 SafetyLayer::limitForce(double nowS, const glm::dvec3& forceN) noexcept {
  const bool finite = std::isfinite(forceN.x) && std::isfinite(forceN.y) && std::isfinite(forceN.z);
  if (!finite) ++stats_.nonFiniteForces;
  glm::dvec3 asked = finite ? forceN : glm::dvec3(0.0);
  double magnitude = glm::length(asked);
  if (magnitude > options_.forceLimitN) {
    asked *= options_.forceLimitN / magnitude;
    magnitude = options_.forceLimitN;
    ++stats_.clampedSteps;
  }
  const bool fault = verdict_.faults != 0 || watchdogActive_ || !finite;
  const auto rampDown = [&]() {
    ++stats_.rampSteps;
    // A hair under the step, so rounding never makes a fall larger than rampOutNPerStep.
    const double fall = options_.rampOutNPerStep * (1.0 - 1e-9);
    const double last = glm::length(lastForceN_);
    if (last <= fall) {
      state_ = ForceState::Off;
      return glm::dvec3(0.0);
    }
    state_ = ForceState::RampOut;
    return lastForceN_ * ((last - fall) / last);
  };
  glm::dvec3 out(0.0);
  switch (state_) {
    case ForceState::Off:
      // The first engagement waits for a small force (a device that starts in the bone does
      // not kick); after a fault the force resumes through the ramp from wherever it is.
      if (!fault && verdict_.valid &&
          (stats_.engagements > 0 || magnitude < options_.engageBelowN)) {
        state_ = ForceState::RampIn;
        rampStartS_ = nowS;
        ++stats_.engagements;
        ++stats_.rampSteps;
      }
      break;
    case ForceState::RampIn:
    case ForceState::Engaged:
      if (fault) {
        out = rampDown();
      } else if (state_ == ForceState::RampIn) {
        const double s = (nowS - rampStartS_) / options_.rampInS;
        if (s >= 1.0) {
          state_ = ForceState::Engaged;
          out = asked;
        } else {
          out = asked * std::max(s, 0.0);
          ++stats_.rampSteps;
        }
      } else {
        out = asked;
      }
      break;
    case ForceState::RampOut:
      out = rampDown();
      break;
  }
  stats_.maxForceN = std::max(stats_.maxForceN, glm::length(out));
  stats_.maxStepChangeN = std::max(stats_.maxStepChangeN, glm::length(out - lastForceN_));
  lastForceN_ = out;
  return out;
}

}  // namespace osteon::devices
