#include "gl_util.h"

#include <stdexcept>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

namespace osteon::viewer {

namespace {

std::string infoLog(GLuint object, bool program) {
  GLint length = 0;
  program ? glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length)
          : glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(std::size_t(length > 0 ? length : 1), '\0');
  program ? glGetProgramInfoLog(object, length, nullptr, log.data())
          : glGetShaderInfoLog(object, length, nullptr, log.data());
  std::string text(log.data());
  for (char& c : text) {
    if (c == '\n') c = ' ';
  }
  return text;
}

GLuint compile(const char* name, GLenum kind, const char* source) {
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(shader, false);
    glDeleteShader(shader);
    throw std::runtime_error(std::string(name) +
                             (kind == GL_VERTEX_SHADER ? " vertex" : " fragment") +
                             " shader: " + log);
  }
  return shader;
}

}  // namespace

GLuint buildProgram(const char* name, const char* vertexSource, const char* fragmentSource) {
  const GLuint vs = compile(name, GL_VERTEX_SHADER, vertexSource);
  const GLuint fs = compile(name, GL_FRAGMENT_SHADER, fragmentSource);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(program, true);
    glDeleteProgram(program);
    throw std::runtime_error(std::string(name) + " program: " + log);
  }
  return program;
}

void deleteBuffer(GLuint id) {
  glDeleteBuffers(1, &id);
}
void deleteVertexArray(GLuint id) {
  glDeleteVertexArrays(1, &id);
}
void deleteTexture(GLuint id) {
  glDeleteTextures(1, &id);
}
void deleteProgram(GLuint id) {
  glDeleteProgram(id);
}

GLuint newBuffer() {
  GLuint id = 0;
  glGenBuffers(1, &id);
  return id;
}

GLuint newVertexArray() {
  GLuint id = 0;
  glGenVertexArrays(1, &id);
  return id;
}

GLuint newTexture() {
  GLuint id = 0;
  glGenTextures(1, &id);
  return id;
}

void configureTexture3D(GLuint texture, GLint filter) {
  glBindTexture(GL_TEXTURE_3D, texture);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, filter);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, filter);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_BASE_LEVEL, 0);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAX_LEVEL, 0);
  for (const GLenum wrap :
       {GLenum(GL_TEXTURE_WRAP_S), GLenum(GL_TEXTURE_WRAP_T), GLenum(GL_TEXTURE_WRAP_R)}) {
    glTexParameteri(GL_TEXTURE_3D, wrap, GL_CLAMP_TO_EDGE);
  }
}

void setUniform(GLuint program, const char* name, const glm::mat4& m) {
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, glm::value_ptr(m));
}
void setUniform(GLuint program, const char* name, const glm::vec3& v) {
  glUniform3fv(glGetUniformLocation(program, name), 1, glm::value_ptr(v));
}
void setUniform(GLuint program, const char* name, const glm::vec4& v) {
  glUniform4fv(glGetUniformLocation(program, name), 1, glm::value_ptr(v));
}
void setUniform(GLuint program, const char* name, const glm::ivec3& v) {
  glUniform3i(glGetUniformLocation(program, name), v.x, v.y, v.z);
}
void setUniform(GLuint program, const char* name, float v) {
  glUniform1f(glGetUniformLocation(program, name), v);
}
void setUniform(GLuint program, const char* name, int v) {
  glUniform1i(glGetUniformLocation(program, name), v);
}

}  // namespace osteon::viewer
