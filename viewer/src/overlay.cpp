#include "overlay.h"

#include <cmath>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "scope.h"
#include "shaders.h"

namespace osteon::viewer {

namespace {

constexpr float kPi = 3.14159265358979f;

// Unit sphere, normals = positions.
void sphereMesh(std::vector<float>& v, std::vector<std::uint32_t>& idx, int slices = 32,
                int stacks = 16) {
  for (int i = 0; i <= stacks; ++i) {
    const float phi = kPi * float(i) / float(stacks);
    for (int j = 0; j <= slices; ++j) {
      const float theta = 2.0f * kPi * float(j) / float(slices);
      const float x = std::sin(phi) * std::cos(theta), y = std::sin(phi) * std::sin(theta),
                  z = std::cos(phi);
      v.insert(v.end(), {x, y, z, x, y, z});
    }
  }
  for (int i = 0; i < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      const std::uint32_t a = std::uint32_t(i * (slices + 1) + j),
                          b = a + std::uint32_t(slices + 1);
      idx.insert(idx.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  }
}

// Radius 1 around z from 0 to 1, open ends.
void cylinderMesh(std::vector<float>& v, std::vector<std::uint32_t>& idx, int slices = 32) {
  for (int j = 0; j <= slices; ++j) {
    const float theta = 2.0f * kPi * float(j) / float(slices);
    const float x = std::cos(theta), y = std::sin(theta);
    v.insert(v.end(), {x, y, 0.0f, x, y, 0.0f, x, y, 1.0f, x, y, 0.0f});
  }
  for (int j = 0; j < slices; ++j) {
    const std::uint32_t a = std::uint32_t(2 * j);
    idx.insert(idx.end(), {a, a + 2, a + 1, a + 1, a + 2, a + 3});
  }
}

// Base radius 1 at z = 0, apex at z = 1, with its base disc.
void coneMesh(std::vector<float>& v, std::vector<std::uint32_t>& idx, int slices = 32) {
  const float s = std::sqrt(0.5f);
  for (int j = 0; j <= slices; ++j) {
    const float theta = 2.0f * kPi * float(j) / float(slices);
    const float x = std::cos(theta), y = std::sin(theta);
    v.insert(v.end(), {x, y, 0.0f, x * s, y * s, s, 0.0f, 0.0f, 1.0f, x * s, y * s, s});
  }
  for (int j = 0; j < slices; ++j) {
    const std::uint32_t a = std::uint32_t(2 * j);
    idx.insert(idx.end(), {a, a + 2, a + 1});
  }
  const std::uint32_t centre = std::uint32_t(v.size() / 6);
  v.insert(v.end(), {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, -1.0f});
  for (int j = 0; j < slices; ++j)
    idx.insert(idx.end(), {centre, std::uint32_t(2 * (j + 1)), std::uint32_t(2 * j)});
}

// The ring between radius 1 and 4 in the z = 0 plane: scaled to the field, it covers the rest
// of the viewport.
void annulusMesh(std::vector<float>& v, std::vector<std::uint32_t>& idx, int slices = 128) {
  for (int j = 0; j <= slices; ++j) {
    const float theta = 2.0f * kPi * float(j) / float(slices);
    const float x = std::cos(theta), y = std::sin(theta);
    v.insert(v.end(), {x, y, 0.0f, 0.0f, 0.0f, 1.0f, 4.0f * x, 4.0f * y, 0.0f, 0.0f, 0.0f, 1.0f});
  }
  for (int j = 0; j < slices; ++j) {
    const std::uint32_t a = std::uint32_t(2 * j);
    idx.insert(idx.end(), {a, a + 1, a + 2, a + 2, a + 1, a + 3});
  }
}

// The model matrix taking the unit z-segment of radius 1 to a..b of radius r.
glm::mat4 segmentModel(const glm::dvec3& a, const glm::dvec3& b, double r) {
  glm::dvec3 w = b - a;
  const double len = glm::length(w);
  const glm::dvec3 axis = len > 1e-12 ? w / len : glm::dvec3(0.0, 0.0, 1.0);
  const glm::dvec3 helper =
      std::abs(axis.z) < 0.9 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(1.0, 0.0, 0.0);
  const glm::dvec3 u = glm::normalize(glm::cross(helper, axis)), v = glm::cross(axis, u);
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(u * r, 0.0);
  m[1] = glm::dvec4(v * r, 0.0);
  m[2] = glm::dvec4(axis * len, 0.0);
  m[3] = glm::dvec4(a, 1.0);
  return glm::mat4(m);
}

}  // namespace

OverlayRenderer::Mesh OverlayRenderer::makeMesh(const std::vector<float>& v,
                                                const std::vector<std::uint32_t>& idx) {
  Mesh m;
  m.vao = GlVertexArray(newVertexArray());
  m.vbo = GlBuffer(newBuffer());
  m.ibo = GlBuffer(newBuffer());
  glBindVertexArray(m.vao.get());
  glBindBuffer(GL_ARRAY_BUFFER, m.vbo.get());
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(v.size() * sizeof(float)), v.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(0));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        reinterpret_cast<void*>(3 * sizeof(float)));
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.ibo.get());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(idx.size() * 4), idx.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  m.indexCount = GLsizei(idx.size());
  return m;
}

OverlayRenderer::OverlayRenderer()
    : program_(buildProgram("overlay", shaders::kOverlayVertex,
                            shaders::withLighting(shaders::kOverlayFragment).c_str())),
      linesVao_(newVertexArray()),
      linesVbo_(newBuffer()) {
  std::vector<float> v;
  std::vector<std::uint32_t> idx;
  sphereMesh(v, idx);
  sphere_ = makeMesh(v, idx);
  v.clear(), idx.clear();
  cylinderMesh(v, idx);
  cylinder_ = makeMesh(v, idx);
  v.clear(), idx.clear();
  coneMesh(v, idx);
  cone_ = makeMesh(v, idx);
  v.clear(), idx.clear();
  annulusMesh(v, idx);
  annulus_ = makeMesh(v, idx);
  glBindVertexArray(linesVao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, linesVbo_.get());
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), reinterpret_cast<void*>(0));
  glVertexAttrib3f(1, 0.0f, 0.0f, 1.0f);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void OverlayRenderer::begin(const FrameCamera& camera) {
  const GLuint p = program_.get();
  glUseProgram(p);
  setUniform(p, "uViewProj", camera.viewProj);
  setLightUniforms(p, camera);
}

void OverlayRenderer::drawMesh(const Mesh& mesh, const glm::mat4& model, const glm::vec4& colour,
                               bool lit) {
  const GLuint p = program_.get();
  setUniform(p, "uModel", model);
  setUniform(p, "uColour", colour);
  setUniform(p, "uLit", lit ? 1 : 0);
  glBindVertexArray(mesh.vao.get());
  glDrawElements(GL_TRIANGLES, mesh.indexCount, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

void OverlayRenderer::drawCapsule(const glm::dvec3& a, const glm::dvec3& b, double r,
                                  const glm::vec4& colour) {
  const glm::mat4 ends(glm::scale(glm::mat4(1.0f), glm::vec3(float(r))));
  drawMesh(sphere_, glm::translate(glm::mat4(1.0f), glm::vec3(a)) * ends, colour, true);
  if (glm::length(b - a) > 1e-9) {
    drawMesh(sphere_, glm::translate(glm::mat4(1.0f), glm::vec3(b)) * ends, colour, true);
    drawMesh(cylinder_, segmentModel(a, b, r), colour, true);
  }
}

void OverlayRenderer::drawTool(const FrameCamera& camera, const simulation::Tool& tool,
                               const simulation::ToolPose& pose, bool drillOn) {
  begin(camera);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  // Cores, opaque: the cutting part gold (orange while drilling), pushing parts steel.
  for (int i = 0; i < tool.partCount; ++i) {
    const simulation::ToolPart& part = tool.parts[std::size_t(i)];
    const glm::vec4 colour = part.cuts ? (drillOn ? glm::vec4(1.0f, 0.62f, 0.18f, 1.0f)
                                                  : glm::vec4(0.85f, 0.72f, 0.35f, 1.0f))
                                       : glm::vec4(0.62f, 0.65f, 0.70f, 1.0f);
    drawCapsule(pose.toWorld(part.aMm), pose.toWorld(part.bMm), part.innerRadiusMm, colour);
  }
  // Contact shells, translucent: back faces first, then front faces, without writing depth.
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  glEnable(GL_CULL_FACE);
  for (const GLenum face : {GLenum(GL_FRONT), GLenum(GL_BACK)}) {
    glCullFace(face);
    for (int i = 0; i < tool.partCount; ++i) {
      const simulation::ToolPart& part = tool.parts[std::size_t(i)];
      const glm::vec4 colour =
          part.cuts ? glm::vec4(0.3f, 0.8f, 1.0f, 0.28f) : glm::vec4(0.3f, 0.8f, 1.0f, 0.16f);
      drawCapsule(pose.toWorld(part.aMm), pose.toWorld(part.bMm), part.outerRadiusMm, colour);
    }
  }
  glDisable(GL_CULL_FACE);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glUseProgram(0);
}

void OverlayRenderer::drawGhost(const FrameCamera& camera, const simulation::Tool& tool,
                                const simulation::ToolPose& commanded,
                                const simulation::ToolPose& proxy) {
  begin(camera);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);  // front faces only: one layer of tint, however the parts overlap
  // Hidden by the bone (depth greater than what is drawn) faint, in the open a little stronger.
  const std::pair<GLenum, float> passes[] = {{GL_GREATER, 0.3f}, {GL_LEQUAL, 0.45f}};
  for (const auto& [depthFunc, alpha] : passes) {
    glDepthFunc(depthFunc);
    for (int i = 0; i < tool.partCount; ++i) {
      const simulation::ToolPart& part = tool.parts[std::size_t(i)];
      drawCapsule(commanded.toWorld(part.aMm), commanded.toWorld(part.bMm), part.innerRadiusMm,
                  glm::vec4(0.62f, 0.76f, 1.0f, alpha));
    }
  }
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
  glUseProgram(0);
  // The spring, over everything: from the proxy's tip to the hand's.
  drawLines(camera, {glm::vec3(proxy.tipMm), glm::vec3(commanded.tipMm)},
            glm::vec4(0.85f, 0.9f, 1.0f, 0.75f));
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}

void OverlayRenderer::drawArrow(const FrameCamera& camera, const glm::dvec3& fromMm,
                                const glm::dvec3& vectorMm, const glm::vec4& colour) {
  const double len = glm::length(vectorMm);
  if (!(len > 1e-6)) return;
  begin(camera);
  glEnable(GL_DEPTH_TEST);
  const glm::dvec3 dir = vectorMm / len;
  const double head = std::min(3.0, 0.4 * len);
  const glm::dvec3 neck = fromMm + dir * (len - head);
  drawMesh(cylinder_, segmentModel(fromMm, neck, 0.3), colour, true);
  drawMesh(cone_, segmentModel(neck, fromMm + vectorMm, 1.0), colour, true);
  glUseProgram(0);
}

void OverlayRenderer::drawMarker(const FrameCamera& camera, const glm::dvec3& pointMm,
                                 double radiusMm, const glm::vec4& colour) {
  begin(camera);
  glEnable(GL_DEPTH_TEST);
  drawCapsule(pointMm, pointMm, radiusMm, colour);
  glUseProgram(0);
}

void OverlayRenderer::drawFieldMask(double aspect) {
  FrameCamera screen;  // identity: the ring is given in normalized device coordinates
  begin(screen);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  const float r = float(Arthroscope::kFieldRadiusNdc);
  drawMesh(annulus_, glm::scale(glm::mat4(1.0f), glm::vec3(r / float(aspect), r, 1.0f)),
           glm::vec4(0.0f, 0.0f, 0.0f, 1.0f), false);
  glEnable(GL_DEPTH_TEST);
  glUseProgram(0);
}

void OverlayRenderer::drawLines(const FrameCamera& camera, const std::vector<glm::vec3>& points,
                                const glm::vec4& colour) {
  if (points.empty()) return;
  begin(camera);
  const GLuint p = program_.get();
  setUniform(p, "uModel", glm::mat4(1.0f));
  setUniform(p, "uColour", colour);
  setUniform(p, "uLit", 0);
  glBindVertexArray(linesVao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, linesVbo_.get());
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(points.size() * sizeof(glm::vec3)), points.data(),
               GL_STREAM_DRAW);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDrawArrays(GL_LINES, 0, GLsizei(points.size()));
  glDisable(GL_BLEND);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glUseProgram(0);
}

}  // namespace osteon::viewer
