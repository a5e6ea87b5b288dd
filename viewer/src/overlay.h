// What is drawn over the bone: the tool (each part's core at its inner radius, opaque, and its
// contact shell at the outer radius, translucent), the ghost of the commanded pose when bone
// holds the tool back, the force as an arrow at the tool, and world-space lines (the
// hierarchy's boxes).
#pragma once

#include <vector>

#include <glm/vec4.hpp>

#include "gl_util.h"
#include "osteon/simulation/tool.h"
#include "renderer.h"

namespace osteon::viewer {

class OverlayRenderer {
 public:
  OverlayRenderer();

  void drawTool(const FrameCamera& camera, const simulation::Tool& tool,
                const simulation::ToolPose& pose, bool drillOn);
  // The commanded pose as a ghost: the same cores, pale and translucent, without writing depth,
  // after everything opaque. Where bone hides it, it shows fainter through the bone, and a line
  // (the coupling's spring) joins its tip to the proxy's.
  void drawGhost(const FrameCamera& camera, const simulation::Tool& tool,
                 const simulation::ToolPose& commanded, const simulation::ToolPose& proxy);
  // An arrow from `fromMm` along `vectorMm` (its length in mm).
  void drawArrow(const FrameCamera& camera, const glm::dvec3& fromMm, const glm::dvec3& vectorMm,
                 const glm::vec4& colour);
  // A lit ball of `radiusMm` at a point (the plan's entry marker, the head's centre).
  void drawMarker(const FrameCamera& camera, const glm::dvec3& pointMm, double radiusMm,
                  const glm::vec4& colour);
  // Black around the arthroscope's circular field (Arthroscope::kFieldRadiusNdc of the
  // viewport's height), over everything drawn in the viewport.
  void drawFieldMask(double aspect);
  // Line segments: points in pairs (mm).
  void drawLines(const FrameCamera& camera, const std::vector<glm::vec3>& points,
                 const glm::vec4& colour);

 private:
  struct Mesh {
    GlVertexArray vao;
    GlBuffer vbo, ibo;
    GLsizei indexCount = 0;
  };
  static Mesh makeMesh(const std::vector<float>& positionsNormals,
                       const std::vector<std::uint32_t>& indices);
  void begin(const FrameCamera& camera);
  void drawMesh(const Mesh& mesh, const glm::mat4& model, const glm::vec4& colour, bool lit);
  // A capsule (a sphere when a == b) of radius r.
  void drawCapsule(const glm::dvec3& a, const glm::dvec3& b, double r, const glm::vec4& colour);

  GlProgram program_;
  Mesh sphere_, cylinder_, cone_, annulus_;
  GlVertexArray linesVao_;
  GlBuffer linesVbo_;
};

}  // namespace osteon::viewer
