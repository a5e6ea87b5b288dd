// Small OpenGL helpers: shader programs that name their failure, and owned GL names.
// Include before GLFW (epoxy must come first).
#pragma once

#include <epoxy/gl.h>
#include <string>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace osteon::viewer {

// A linked program from vertex and fragment source; throws std::runtime_error with the
// compiler's log (an internal error: the sources are ours).
GLuint buildProgram(const char* name, const char* vertexSource, const char* fragmentSource);

// A GL name deleted with its object.
template <void (*Delete)(GLuint)>
class GlName {
 public:
  GlName() = default;
  explicit GlName(GLuint id) : id_(id) {}
  ~GlName() { reset(); }
  GlName(GlName&& o) noexcept : id_(o.id_) { o.id_ = 0; }
  GlName& operator=(GlName&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      o.id_ = 0;
    }
    return *this;
  }
  GlName(const GlName&) = delete;
  GlName& operator=(const GlName&) = delete;
  GLuint get() const { return id_; }
  void reset() {
    if (id_) Delete(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

void deleteBuffer(GLuint id);
void deleteVertexArray(GLuint id);
void deleteTexture(GLuint id);
void deleteProgram(GLuint id);
using GlBuffer = GlName<deleteBuffer>;
using GlVertexArray = GlName<deleteVertexArray>;
using GlTexture = GlName<deleteTexture>;
using GlProgram = GlName<deleteProgram>;

GLuint newBuffer();
GLuint newVertexArray();
GLuint newTexture();
// Binds a 3D texture and sets it up: one level, edges clamped, `filter` both ways.
void configureTexture3D(GLuint texture, GLint filter);

// Uniform setters by name (a missing uniform, optimised away, is ignored).
void setUniform(GLuint program, const char* name, const glm::mat4& m);
void setUniform(GLuint program, const char* name, const glm::vec3& v);
void setUniform(GLuint program, const char* name, const glm::vec4& v);
void setUniform(GLuint program, const char* name, const glm::ivec3& v);
void setUniform(GLuint program, const char* name, float v);
void setUniform(GLuint program, const char* name, int v);

}  // namespace osteon::viewer
