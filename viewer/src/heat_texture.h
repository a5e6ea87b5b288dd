// The heat view's texture (docs/feel.md, Heat): the thermal model's temperatures (°C) as a
// float 3D texture, filtered linearly, bound at unit 2 for the bone shader's mode 5. Each
// update uploads only the cells the model has ever warmed.
#pragma once

#include <vector>

#include "gl_util.h"
#include "osteon/simulation/thermal.h"

namespace osteon::viewer {

class HeatTexture {
 public:
  // On the thread that diffuses the model (the render loop). A new model (another bone) gets a
  // new texture at its initial temperature.
  void update(const simulation::ThermalModel& heat);
  void reset() { texture_.reset(), model_ = nullptr; }
  bool available() const { return model_ != nullptr; }
  void bind(GLuint program) const;

 private:
  GlTexture texture_;
  const simulation::ThermalModel* model_ = nullptr;
  glm::ivec3 dims_{0};
  glm::dvec3 originMm_{0.0};
  double cellMm_ = 1.0;
  std::vector<float> staging_;
};

}  // namespace osteon::viewer
