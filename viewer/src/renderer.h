// The bone on the GPU: the live crack-free surface uploaded incrementally (SurfaceUploader over
// GL buffers), the naive comparison surface uploaded whole, and the draw in every view.
#pragma once

#include <cstddef>

#include "gl_util.h"
#include "heat_texture.h"
#include "options.h"
#include "osteon/geometry/surface/surface.h"
#include "surface_upload.h"
#include "voxel_textures.h"

namespace osteon::viewer {

// SurfaceUploadTarget over a vertex array with one vertex and one index buffer.
class GlSurfaceBuffers : public SurfaceUploadTarget {
 public:
  GlSurfaceBuffers();
  void reallocateVertices(std::size_t capacity, const GpuVertex* data, std::size_t count) override;
  void writeVertices(std::size_t first, std::size_t count, const GpuVertex* data) override;
  void reallocateIndices(std::size_t capacity, const std::uint32_t* data,
                         std::size_t count) override;
  void writeIndices(std::size_t first, std::size_t count, const std::uint32_t* data) override;
  GLuint vertexArray() const { return vao_.get(); }

 private:
  GlVertexArray vao_;
  GlBuffer vbo_, ibo_;
};

// What one frame's draw needs from the camera.
struct FrameCamera {
  glm::mat4 viewProj{1.0f};
  glm::vec3 eye{0.0f};
  glm::vec3 light{0.0f, 0.0f, 1.0f};  // unit, towards the light
  // The arthroscope's spotlight at its tip instead of the headlight.
  bool spot = false;
  glm::vec3 spotPos{0.0f}, spotDir{0.0f, 0.0f, -1.0f};
  float spotCos = 0.5f;   // of the cone's half angle
  float spotGain = 1.0f;  // the light source's setting
};

// The uniforms of the lighting both programs share (shaders.h).
void setLightUniforms(GLuint program, const FrameCamera& camera);

class BoneRenderer {
 public:
  BoneRenderer();  // compiles the program (throws std::runtime_error on a driver's refusal)

  // A new bone: both surfaces forgotten, the voxel textures made for its grid. Returns "" or
  // why the level and density views are unavailable.
  std::string resetScene(const geometry::VoxelGrid& grid);

  // The live surface's changes, uploaded incrementally.
  const UploadStats& applyChanges(const geometry::SurfaceDelta& delta) {
    return uploader_.apply(delta);
  }
  // The naive comparison surface, uploaded whole (glBufferData).
  void uploadWhole(const geometry::SurfaceMesh& mesh);

  // Draws the chosen surface in `view` (Hierarchy draws as Shaded; the boxes are overlays);
  // wire: the edges on top.
  void draw(const FrameCamera& camera, View view, SurfaceChoice surface, bool wire);

  std::size_t triangles(SurfaceChoice surface) const {
    return surface == SurfaceChoice::Naive ? wholeIndexCount_ / 3 : uploader_.triangleCount();
  }
  VoxelTextures& textures() { return textures_; }
  HeatTexture& heat() { return heat_; }

 private:
  void drawElements(SurfaceChoice surface);

  GlProgram program_;
  GlSurfaceBuffers live_;
  SurfaceUploader uploader_{live_};
  GlVertexArray wholeVao_;
  GlBuffer wholeVbo_, wholeIbo_;
  std::size_t wholeIndexCount_ = 0;
  VoxelTextures textures_;
  HeatTexture heat_;
};

}  // namespace osteon::viewer
