#include "renderer.h"

#include <cstdint>
#include <vector>

#include "shaders.h"

namespace osteon::viewer {

namespace {

// Position and normal of a GpuVertex at attributes 0 and 1 of the bound vertex array.
void describeVertices() {
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(GpuVertex), reinterpret_cast<void*>(0));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(GpuVertex),
                        reinterpret_cast<void*>(3 * sizeof(float)));
}

}  // namespace

void setLightUniforms(GLuint program, const FrameCamera& camera) {
  setUniform(program, "uEye", camera.eye);
  setUniform(program, "uLight", camera.light);
  setUniform(program, "uSpot", camera.spot ? 1 : 0);
  setUniform(program, "uSpotPos", camera.spotPos);
  setUniform(program, "uSpotDir", camera.spotDir);
  setUniform(program, "uSpotCos", camera.spotCos);
  setUniform(program, "uSpotGain", camera.spotGain);
}

GlSurfaceBuffers::GlSurfaceBuffers()
    : vao_(newVertexArray()), vbo_(newBuffer()), ibo_(newBuffer()) {
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
  describeVertices();
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_.get());
  glBindVertexArray(0);
}

void GlSurfaceBuffers::reallocateVertices(std::size_t capacity, const GpuVertex* data,
                                          std::size_t count) {
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(capacity * sizeof(GpuVertex)), nullptr, GL_DYNAMIC_DRAW);
  if (count > 0) glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(count * sizeof(GpuVertex)), data);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void GlSurfaceBuffers::writeVertices(std::size_t first, std::size_t count, const GpuVertex* data) {
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.get());
  glBufferSubData(GL_ARRAY_BUFFER, GLintptr(first * sizeof(GpuVertex)),
                  GLsizeiptr(count * sizeof(GpuVertex)), data);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void GlSurfaceBuffers::reallocateIndices(std::size_t capacity, const std::uint32_t* data,
                                         std::size_t count) {
  // The element buffer belongs to the vertex array: bind that, not the buffer alone.
  glBindVertexArray(vao_.get());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(capacity * 4), nullptr, GL_DYNAMIC_DRAW);
  if (count > 0) glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, GLsizeiptr(count * 4), data);
  glBindVertexArray(0);
}

void GlSurfaceBuffers::writeIndices(std::size_t first, std::size_t count,
                                    const std::uint32_t* data) {
  glBindVertexArray(vao_.get());
  glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, GLintptr(first * 4), GLsizeiptr(count * 4), data);
  glBindVertexArray(0);
}

BoneRenderer::BoneRenderer()
    : program_(buildProgram("bone", shaders::kBoneVertex,
                            shaders::withLighting(shaders::kBoneFragment).c_str())),
      wholeVao_(newVertexArray()),
      wholeVbo_(newBuffer()),
      wholeIbo_(newBuffer()) {
  glBindVertexArray(wholeVao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, wholeVbo_.get());
  describeVertices();
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, wholeIbo_.get());
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

std::string BoneRenderer::resetScene(const geometry::VoxelGrid& grid) {
  uploader_.reset();
  uploader_.setNormalField(&grid);  // the live surface shades with the fill's gradient
  wholeIndexCount_ = 0;
  heat_.reset();
  return textures_.reset(grid);
}

void BoneRenderer::uploadWhole(const geometry::SurfaceMesh& mesh) {
  std::vector<GpuVertex> vertices(mesh.vertexCount());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const glm::dvec3& p = mesh.positionsMm[i];
    const glm::dvec3 n = i < mesh.normals.size() ? mesh.normals[i] : glm::dvec3(0.0);
    vertices[i] = {{float(p.x), float(p.y), float(p.z)}, {float(n.x), float(n.y), float(n.z)}};
  }
  glBindVertexArray(wholeVao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, wholeVbo_.get());
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(GpuVertex)), vertices.data(),
               GL_STREAM_DRAW);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.triangleCount() * 12),
               mesh.triangles.data(), GL_STREAM_DRAW);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  wholeIndexCount_ = 3 * mesh.triangleCount();
}

void BoneRenderer::drawElements(SurfaceChoice surface) {
  if (surface == SurfaceChoice::Naive) {
    if (wholeIndexCount_ == 0) return;
    glBindVertexArray(wholeVao_.get());
    glDrawElements(GL_TRIANGLES, GLsizei(wholeIndexCount_), GL_UNSIGNED_INT, nullptr);
  } else {
    if (uploader_.indexEnd() == 0) return;
    glBindVertexArray(live_.vertexArray());
    glDrawElements(GL_TRIANGLES, GLsizei(uploader_.indexEnd()), GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
}

void BoneRenderer::draw(const FrameCamera& camera, View view, SurfaceChoice surface, bool wire) {
  const GLuint p = program_.get();
  glUseProgram(p);
  setUniform(p, "uViewProj", camera.viewProj);
  setLightUniforms(p, camera);
  textures_.bind(p);
  int mode = 0;
  if (view == View::Cracks) mode = 1;
  if (view == View::Levels && textures_.available()) mode = 2;
  if (view == View::Density && textures_.available()) mode = 3;
  if (view == View::Heat && heat_.available()) {
    heat_.bind(p);
    mode = 5;
  }
  setUniform(p, "uMode", mode);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);  // back faces are drawn: the crack view is about them
  glDisable(GL_BLEND);
  drawElements(surface);
  // No edges over the crack view: its pixels are the metric.
  if ((wire && view != View::Cracks) || view == View::Wireframe) {
    setUniform(p, "uMode", 4);
    setUniform(p, "uFlat", glm::vec4(0.15f, 0.17f, 0.2f, 1.0f));
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glEnable(GL_POLYGON_OFFSET_LINE);
    glPolygonOffset(-1.0f, -1.0f);
    drawElements(surface);
    glDisable(GL_POLYGON_OFFSET_LINE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }
  glUseProgram(0);
}

}  // namespace osteon::viewer
