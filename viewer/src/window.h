// The viewer's C handles, each owned by an object whose destructor releases it (style rule 7):
// GLFW itself, its window, and Dear ImGui's context with its GLFW and OpenGL 3 back ends.
// Declared in this order in App, they are released in the reverse order, after the GL objects
// declared below them, while the context those objects belong to still exists.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

struct GLFWwindow;

namespace osteon::viewer {

// A window that cannot open (no DISPLAY, no GL 3.3): exit 2 with this one line.
class WindowError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// glfwInit on construction (WindowError when it fails), glfwTerminate on destruction.
class GlfwLibrary {
 public:
  GlfwLibrary();
  ~GlfwLibrary();
  GlfwLibrary(const GlfwLibrary&) = delete;
  GlfwLibrary& operator=(const GlfwLibrary&) = delete;
};

struct GlfwWindowDeleter {
  void operator()(GLFWwindow* window) const noexcept;
};
using GlfwWindowPtr = std::unique_ptr<GLFWwindow, GlfwWindowDeleter>;

// A window with an OpenGL 3.3 core context, current on this thread, with no multisampling (the
// crack metric counts exact colours); vsync unless `asFastAsItCan`. WindowError when it fails.
GlfwWindowPtr openWindow(int width, int height, const std::string& title, bool asFastAsItCan);

// ImGui's context and its back ends on `window`, installed after the window's own callbacks
// (ImGui chains to them); shut down in the reverse order.
class ImGuiSession {
 public:
  explicit ImGuiSession(GLFWwindow* window);
  ~ImGuiSession();
  ImGuiSession(const ImGuiSession&) = delete;
  ImGuiSession& operator=(const ImGuiSession&) = delete;
};

}  // namespace osteon::viewer
