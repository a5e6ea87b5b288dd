// The Geomagic Touch through OpenHaptics' HD API (built with -DOSTEON_OPENHAPTICS=ON).
// Compiled here only against the SDK, and in tests against a fake HD API that records the
// calls (tests/devices/fake_openhaptics): keep to the HD calls that fake knows.
#include <HD/hd.h>
#include <atomic>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include "osteon/core/error.h"
#include "osteon/core/handoff.h"
#include "osteon/devices/touch.h"

namespace osteon::devices {

namespace {

std::string hdErrorText(const HDErrorInfo& error) {
  const char* text = hdGetErrorString(error.errorCode);
  return text ? std::string(text) : "HD error " + std::to_string(int(error.errorCode));
}

class TouchDevice final : public Device {
 public:
  TouchDevice(const std::string& name, const std::string& configName, const TouchOptions& options)
      : Device(name), options_(options) {
    device_ = hdInitDevice(configName.empty() ? HD_DEFAULT_DEVICE : configName.c_str());
    HDErrorInfo error = hdGetError();
    if (HD_DEVICE_ERROR(error))
      throw InputError(name + ": cannot initialise the Touch (" + hdErrorText(error) + ")");
    hdMakeCurrentDevice(device_);
    hdEnable(HD_FORCE_OUTPUT);
    scheduled_ = hdScheduleAsynchronous(&TouchDevice::servo, this, HD_MAX_SCHEDULER_PRIORITY);
    hdStartScheduler();
    error = hdGetError();
    if (HD_DEVICE_ERROR(error)) {
      shutDown();
      throw InputError(name + ": cannot start the servo loop (" + hdErrorText(error) + ")");
    }
  }
  ~TouchDevice() override { shutDown(); }

  Capabilities capabilities() const override {
    Capabilities c;
    c.pose = true;
    c.buttons = true;
    c.force = true;
    c.maxForceN = options_.maxForceN;
    return c;
  }

  void poll(double nowS, DeviceSample& sample) noexcept override {
    bool fresh = false;
    const ServoState s = fromServo_.read(&fresh);
    if (fresh && s.ticks != polledTicks_) {
      polledTicks_ = s.ticks;
      polledAtS_ = nowS;
    }
    if (s.ticks == 0) {
      sample = DeviceSample{};
      return;
    }
    sample.tS = polledAtS_;
    sample.positionMm = s.positionMm;
    sample.orientation = s.orientation;
    sample.buttons = s.buttons;
    sample.drillOn = (s.buttons & options_.drillButtonMask) != 0;
    sample.connected = s.errors == errorsSeen_;
    errorsSeen_ = s.errors;
  }

  void setForce(double, const glm::dvec3& forceN) noexcept override {
    ++forceSeq_;
    toServo_.write(ForceCommand{forceN, forceSeq_});
  }

 private:
  struct ServoState {
    glm::dvec3 positionMm{0.0};
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
    std::uint32_t buttons = 0;
    std::uint64_t ticks = 0;
    std::uint64_t errors = 0;
  };
  struct ForceCommand {
    glm::dvec3 forceN{0.0};
    std::uint64_t seq = 0;
  };

  // The servo loop (OpenHaptics' scheduler thread, 1 kHz): pose in, force out.
  static HDCallbackCode HDCALLBACK servo(void* self) {
    return static_cast<TouchDevice*>(self)->servoTick();
  }

  HDCallbackCode servoTick() noexcept {
    hdBeginFrame(device_);
    HDdouble transform[16];
    HDint buttons = 0;
    hdGetDoublev(HD_CURRENT_TRANSFORM, transform);
    hdGetIntegerv(HD_CURRENT_BUTTONS, &buttons);
    // Column-major 4x4: the rotation's columns, then the position in mm.
    const glm::dmat3 rotation(transform[0], transform[1], transform[2], transform[4], transform[5],
                              transform[6], transform[8], transform[9], transform[10]);
    state_.positionMm = glm::dvec3(transform[12], transform[13], transform[14]);
    state_.orientation = glm::normalize(glm::quat_cast(rotation));
    state_.buttons = std::uint32_t(buttons);
    ++state_.ticks;

    // The force: the haptic loop's latest, unless it stopped sending (then ramped out here).
    const ForceCommand command = toServo_.read();
    if (command.seq != lastSeq_) {
      lastSeq_ = command.seq;
      staleTicks_ = 0;
      glm::dvec3 f = command.forceN;
      const double m = glm::length(f);
      if (!std::isfinite(m)) {
        f = glm::dvec3(0.0);
      } else if (m > options_.maxForceN) {
        f *= options_.maxForceN / m;
      }
      output_ = f;
    } else if (++staleTicks_ > options_.staleServoTicks) {
      const double fall =
          options_.rampOutNPerTick * (1.0 - 1e-9);  // rounding never passes the step
      const double m = glm::length(output_);
      output_ = m <= fall ? glm::dvec3(0.0) : output_ * ((m - fall) / m);
    }
    const HDdouble force[3] = {output_.x, output_.y, output_.z};
    hdSetDoublev(HD_CURRENT_FORCE, force);
    hdEndFrame(device_);

    const HDErrorInfo error = hdGetError();
    if (HD_DEVICE_ERROR(error)) ++state_.errors;  // reported as a disconnected sample
    fromServo_.write(state_);
    return HD_CALLBACK_CONTINUE;
  }

  void shutDown() noexcept {
    if (stopped_) return;
    stopped_ = true;
    hdStopScheduler();
    if (scheduled_ != HDSchedulerHandle(0)) hdUnschedule(scheduled_);
    hdDisableDevice(device_);
  }

  TouchOptions options_;
  HHD device_{};
  HDSchedulerHandle scheduled_{};
  bool stopped_ = false;
  // servo thread
  ServoState state_;
  std::uint64_t lastSeq_ = 0;
  int staleTicks_ = 0;
  glm::dvec3 output_{0.0};
  // polling thread
  std::uint64_t polledTicks_ = 0;
  std::uint64_t errorsSeen_ = 0;
  double polledAtS_ = -1.0;
  std::uint64_t forceSeq_ = 0;
  core::TripleBuffer<ServoState> fromServo_;
  core::TripleBuffer<ForceCommand> toServo_;
};

}  // namespace

bool touchAvailable() {
  return true;
}

std::unique_ptr<Device> openTouch(const std::string& deviceName, const std::string& configName,
                                  const TouchOptions& options) {
  return std::make_unique<TouchDevice>(deviceName, configName, options);
}

}  // namespace osteon::devices
