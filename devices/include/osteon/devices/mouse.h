// `mouse`: the device a front end feeds from its own input (the viewer's mouse and keyboard).
// The render loop sets the tool's pose as the user drags; the haptic loop polls it. The pose
// holds between frames, so a sample is fresh at every poll; a front end that stops feeding for
// staleAfterS makes the device report itself disconnected (a gap for the safety layer).
#pragma once

#include "osteon/core/handoff.h"
#include "osteon/devices/device.h"

namespace osteon::devices {

struct MouseState {
  glm::dvec3 positionMm{0.0};
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
  std::uint32_t buttons = 0;
  bool drillOn = false;
  double fedAtS = -1.0;  // steadyNowS() when fed
};

class MouseDevice final : public Device {
 public:
  explicit MouseDevice(const std::string& name = "mouse", double staleAfterS = 0.5);
  Capabilities capabilities() const override;
  // From the render loop (one thread): the pose the user's input gives now. No lock, no heap.
  void feed(const glm::dvec3& positionMm, const glm::dquat& orientation, std::uint32_t buttons,
            bool drillOn) noexcept;
  void poll(double nowS, DeviceSample& sample) noexcept override;

 private:
  core::TripleBuffer<MouseState> state_;
  MouseState last_;
  double staleAfterS_;
};

}  // namespace osteon::devices
