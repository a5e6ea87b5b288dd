#include "window.h"

#include "gl_util.h"  // epoxy before GLFW

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

namespace osteon::viewer {

namespace {

// GLFW reports why through a callback; the latest reason goes into the WindowError.
std::string& glfwError() {
  static std::string text = "unknown GLFW error";
  return text;
}

void onGlfwError(int, const char* text) {
  glfwError() = text ? text : "unknown GLFW error";
}

}  // namespace

GlfwLibrary::GlfwLibrary() {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) throw WindowError("cannot open a window: " + glfwError());
}

GlfwLibrary::~GlfwLibrary() {
  glfwTerminate();
}

void GlfwWindowDeleter::operator()(GLFWwindow* window) const noexcept {
  glfwDestroyWindow(window);
}

GlfwWindowPtr openWindow(int width, int height, const std::string& title, bool asFastAsItCan) {
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  glfwWindowHint(GLFW_SAMPLES, 0);
  GlfwWindowPtr window(glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr));
  if (!window) throw WindowError("cannot open a window: " + glfwError());
  glfwMakeContextCurrent(window.get());
  glfwSwapInterval(asFastAsItCan ? 0 : 1);
  return window;
}

ImGuiSession::ImGuiSession(GLFWwindow* window) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working folder
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);  // chains to the window's callbacks
  ImGui_ImplOpenGL3_Init("#version 330 core");
}

ImGuiSession::~ImGuiSession() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

}  // namespace osteon::viewer
