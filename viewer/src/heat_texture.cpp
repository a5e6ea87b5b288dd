#include "heat_texture.h"

namespace osteon::viewer {

void HeatTexture::update(const simulation::ThermalModel& heat) {
  if (model_ != &heat || dims_ != heat.dims()) {
    model_ = &heat;
    dims_ = heat.dims();
    originMm_ = heat.originMm();
    cellMm_ = heat.cellMm();
    texture_ = GlTexture(newTexture());
    configureTexture3D(texture_.get(), GL_LINEAR);  // °C between cell centres
    const std::size_t cells = std::size_t(dims_.x) * std::size_t(dims_.y) * std::size_t(dims_.z);
    staging_.assign(cells, float(heat.options().initialC));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage3D(GL_TEXTURE_3D, 0, GL_R32F, dims_.x, dims_.y, dims_.z, 0, GL_RED, GL_FLOAT,
                 staging_.data());
  }
  glm::ivec3 lo, hi;
  heat.touchedCells(lo, hi);
  if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) return;
  const glm::ivec3 n = hi - lo + 1;
  staging_.resize(std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z));
  heat.copyC(lo, hi, staging_.data());
  glBindTexture(GL_TEXTURE_3D, texture_.get());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexSubImage3D(GL_TEXTURE_3D, 0, lo.x, lo.y, lo.z, n.x, n.y, n.z, GL_RED, GL_FLOAT,
                  staging_.data());
}

void HeatTexture::bind(GLuint program) const {
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_3D, texture_.get());
  glActiveTexture(GL_TEXTURE0);
  setUniform(program, "uHeat", 2);
  setUniform(program, "uHeatOrigin", glm::vec3(originMm_));
  setUniform(program, "uHeatSpan", glm::vec3(glm::dvec3(glm::max(dims_, glm::ivec3(1))) * cellMm_));
}

}  // namespace osteon::viewer
