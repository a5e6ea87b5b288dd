// Keyboard, mouse and file drops, the panels' requests, loading another bone and recording.
#include "app.h"
#include "gl_util.h"  // epoxy before GLFW

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <chrono>
#include <imgui.h>
#include <new>

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_file.h"

namespace osteon::viewer {

namespace {

constexpr double kRadiansPerPixel = 0.01;
constexpr double kDepthStepMm = 1.0;     // Ctrl + wheel, Page Up / Down: along the view
constexpr double kAdvanceStepMm = 0.25;  // Up / Down, Shift + wheel: along the tool's axis
constexpr double kLensStepRad = 3.14159265358979 / 12.0;  // , and . turn the scope's lens 15 deg
constexpr double kLightStep = 1.25;                       // - and = dim and brighten its light

bool held(GLFWwindow* w, int key, int other) {
  return glfwGetKey(w, key) == GLFW_PRESS || glfwGetKey(w, other) == GLFW_PRESS;
}

}  // namespace

void App::onKey(int key, int action, int mods) {
  if (action == GLFW_RELEASE) return;
  const bool press = action == GLFW_PRESS;
  // Esc asks first: Enter or Y quits, Esc or N stays.
  if (panel_.confirmQuit && press) {
    if (key == GLFW_KEY_ENTER || key == GLFW_KEY_KP_ENTER || key == GLFW_KEY_Y) {
      panel_.confirmQuit = false;  // the last frame shows the view, not the question
      glfwSetWindowShouldClose(window_.get(), GLFW_TRUE);
    }
    if (key == GLFW_KEY_ESCAPE || key == GLFW_KEY_N) panel_.confirmQuit = false;
    return;
  }
  if (options_.ui && ImGui::GetIO().WantCaptureKeyboard) return;
  const bool mouseTool = !scene_->poseSource().followsPath();
  // Movement keys repeat; everything else acts once per press.
  switch (key) {
    case GLFW_KEY_UP:
    case GLFW_KEY_DOWN:
      if (mouseTool)
        moveToolAlong(target_.forward(), key == GLFW_KEY_UP ? kAdvanceStepMm : -kAdvanceStepMm);
      return;
    case GLFW_KEY_PAGE_UP:
    case GLFW_KEY_PAGE_DOWN:
      if (mouseTool)
        moveToolAlong(viewBasis().forward,
                      key == GLFW_KEY_PAGE_DOWN ? kDepthStepMm : -kDepthStepMm);
      return;
    default:
      break;
  }
  if (!press) return;
  if (key >= GLFW_KEY_F2 && key <= GLFW_KEY_F7) {
    panel_.view = View(key - GLFW_KEY_F1);
    return;
  }
  const bool shift = (mods & GLFW_MOD_SHIFT) != 0;
  // F1 and ? (Shift + / on most layouts) show the keys.
  if (key == GLFW_KEY_F1 || (key == GLFW_KEY_SLASH && shift)) {
    panel_.showHelp = !panel_.showHelp;
    return;
  }
  if (key == GLFW_KEY_F && shift) {
    panel_.focusTool = true;
    return;
  }
  if (key >= GLFW_KEY_1 && key <= GLFW_KEY_6) {
    panel_.axisView = AxisView(key - GLFW_KEY_1);
    return;
  }
  onCommandKey(key);
}

// The keys that act once per press and have no modifier of their own.
void App::onCommandKey(int key) {
  switch (key) {
    case GLFW_KEY_ESCAPE:
      if (panel_.showHelp) {
        panel_.showHelp = false;
      } else {
        panel_.confirmQuit = true;
      }
      break;
    case GLFW_KEY_BACKSPACE:
      panel_.resetBone = true;
      break;
    case GLFW_KEY_E:
      panel_.scoreTrial = true;
      break;
    case GLFW_KEY_O:
      panel_.showPlan = !panel_.showPlan;
      break;
    case GLFW_KEY_V:
      cycleCamera();
      break;
    case GLFW_KEY_P:
      panel_.pictureInPicture = !panel_.pictureInPicture;
      break;
    case GLFW_KEY_COMMA:
    case GLFW_KEY_PERIOD:
      scope_.rotateLens(key == GLFW_KEY_COMMA ? -kLensStepRad : kLensStepRad);
      break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_EQUAL:
      scope_.dimLight(key == GLFW_KEY_MINUS ? 1.0 / kLightStep : kLightStep);
      break;
    case GLFW_KEY_TAB:
      options_.ui = !options_.ui;
      break;
    case GLFW_KEY_SPACE:
      panel_.toggleDrill = true;
      break;
    case GLFW_KEY_R:
      panel_.toggleRecord = true;
      break;
    case GLFW_KEY_F:
      panel_.frameBone = true;
      break;
    case GLFW_KEY_T:
      panel_.resetTool = true;
      break;
    case GLFW_KEY_W:
      panel_.wire = !panel_.wire;
      break;
    case GLFW_KEY_G:
      panel_.showTool = !panel_.showTool;
      break;
    case GLFW_KEY_A:
      sound_->toggleMute();
      break;
    case GLFW_KEY_M:
      panel_.method =
          panel_.method == SurfaceChoice::Naive ? SurfaceChoice::CrackFree : SurfaceChoice::Naive;
      break;
    case GLFW_KEY_S:
      panel_.view = View::Shaded;
      break;
    case GLFW_KEY_C:
      panel_.view = View::Cracks;
      break;
    case GLFW_KEY_L:
      panel_.view = View::Levels;
      break;
    case GLFW_KEY_D:
      panel_.view = View::Density;
      break;
    case GLFW_KEY_H:
      panel_.view = View::Hierarchy;
      break;
    case GLFW_KEY_B:  // the bone's heat ("burn")
      panel_.view = View::Heat;
      break;
    case GLFW_KEY_I:
      panel_.irrigation = !panel_.irrigation;
      break;
    case GLFW_KEY_LEFT_BRACKET:
      panel_.hierarchyLevel = std::max(panel_.hierarchyLevel - 1, 0);
      break;
    case GLFW_KEY_RIGHT_BRACKET:
      panel_.hierarchyLevel =
          std::min(panel_.hierarchyLevel + 1, std::max(hierarchy_.levelCount() - 1, 0));
      break;
    default:
      break;
  }
}

void App::onMouseButton(int button, int action, int mods) {
  mods_ = mods;
  const bool down = action == GLFW_PRESS;
  // A drag that starts over a panel belongs to the panel.
  if (down && options_.ui && ImGui::GetIO().WantCaptureMouse) return;
  if (button == GLFW_MOUSE_BUTTON_LEFT) leftDown_ = down;
  if (button == GLFW_MOUSE_BUTTON_MIDDLE) middleDown_ = down;
  if (button == GLFW_MOUSE_BUTTON_RIGHT) rightDown_ = down;
}

void App::onCursor(double x, double y) {
  const double dx = x - cursorX_, dy = y - cursorY_;
  cursorX_ = x;
  cursorY_ = y;
  int w = 0, h = 0;
  glfwGetWindowSize(window_.get(), &w, &h);
  const bool shift = held(window_.get(), GLFW_KEY_LEFT_SHIFT, GLFW_KEY_RIGHT_SHIFT);
  const bool turn = held(window_.get(), GLFW_KEY_LEFT_CONTROL, GLFW_KEY_RIGHT_CONTROL) ||
                    held(window_.get(), GLFW_KEY_LEFT_ALT, GLFW_KEY_RIGHT_ALT);
  const CameraMode mode = panel_.cameraMode;
  if (leftDown_ && mode == CameraMode::Scope) {
    scope_.pivot(dx, dy);  // the scope swings about its portal
  } else if (leftDown_ && mode == CameraMode::Follow) {
    follow_.rotate(dx, dy);
  } else if (mode == CameraMode::Orbit && (middleDown_ || (leftDown_ && shift))) {
    camera_.pan(dx, dy, h);
  } else if (leftDown_) {
    camera_.rotate(dx, dy);
  } else if (rightDown_ && !scene_->poseSource().followsPath()) {
    turn ? turnTool(dx, dy) : moveToolInView(dx, dy);
  }
}

void App::onScroll(double dy) {
  if (options_.ui && ImGui::GetIO().WantCaptureMouse) return;
  const bool mouseTool = !scene_->poseSource().followsPath();
  if (mouseTool && held(window_.get(), GLFW_KEY_LEFT_CONTROL, GLFW_KEY_RIGHT_CONTROL)) {
    moveToolAlong(viewBasis().forward, -dy * kDepthStepMm);  // wheel away: deeper into the view
  } else if (mouseTool && held(window_.get(), GLFW_KEY_LEFT_SHIFT, GLFW_KEY_RIGHT_SHIFT)) {
    moveToolAlong(target_.forward(), dy * kAdvanceStepMm);
  } else {
    zoomAtCursor(dy);
  }
}

void App::onDrop(const std::string& path) {
  std::snprintf(panel_.openPath, sizeof panel_.openPath, "%s", path.c_str());
  panel_.openUnitMm.reset();  // a dropped file's unit is asked for that file
  panel_.open = true;
}

void App::publishTarget() {
  if (!scene_->poseSource().followsPath()) scene_->poseSource().setTarget(target_, drillOn_);
}

void App::moveToolInView(double dxPixels, double dyPixels) {
  int w = 0, h = 0;
  glfwGetWindowSize(window_.get(), &w, &h);
  const ViewBasis view = viewBasis();
  const double mm = view.mmPerPixelAt(target_.tipMm, h);
  target_.tipMm += (dxPixels * view.right - dyPixels * view.up) * mm;
  publishTarget();
}

void App::moveToolAlong(const glm::dvec3& direction, double mm) {
  target_.tipMm += direction * mm;
  publishTarget();
}

void App::turnTool(double dxPixels, double dyPixels) {
  // About the tip, around the view's axes: the shaft swings with the cursor.
  const ViewBasis view = viewBasis();
  const glm::dquat q = glm::angleAxis(dxPixels * kRadiansPerPixel, view.up) *
                       glm::angleAxis(dyPixels * kRadiansPerPixel, view.right);
  target_.orientation = glm::normalize(q * target_.orientation);
  publishTarget();
}

void App::handleRequests() {
  if (panel_.toggleDrill) {
    drillOn_ = !drillOn_;
    publishTarget();
  }
  if (panel_.resetTool) {
    target_ = scene_->initialPose();
    publishTarget();
  }
  if (panel_.toggleRecord) toggleRecording();
  if (panel_.frameBone) camera_.frame(scene_->boundsMin(), scene_->boundsMax());
  // An axis view turns the orbit camera about its target: the zoom stays.
  if (panel_.axisView) {
    camera_.setAxisView(*panel_.axisView);
    panel_.cameraMode = CameraMode::Orbit;
  }
  if (panel_.focusTool) focusOnTool();
  if (panel_.scoreTrial) scoreTrial();
  if (panel_.quit) {
    panel_.confirmQuit = false;
    glfwSetWindowShouldClose(window_.get(), GLFW_TRUE);
  }
  if (panel_.resetBone) startLoading(scene_->request(), "the bone, as it was");
  if (panel_.open) openFile(panel_.openPath);
  panel_.toggleDrill = panel_.resetTool = panel_.toggleRecord = panel_.frameBone = panel_.open =
      panel_.focusTool = panel_.resetBone = panel_.quit = panel_.scoreTrial = false;
  panel_.axisView.reset();
  // A recording the haptic loop has let go of (stopped, or full) is written now.
  if (scene_->poseSource().recorder().finished()) finishRecording(false);
}

void App::toggleRecording() {
  PathRecorder& recorder = scene_->poseSource().recorder();
  if (recorder.recording()) {
    recorder.requestStop();
    panel_.recordMessage = "stopping ...";
    return;
  }
  if (recorder.finished()) return;  // being written
  recordTarget_ = panel_.recordPath;
  if (recordTarget_.empty()) recordTarget_ = "osteon-path.csv";
  if (recorder.start()) panel_.recordMessage = "recording to " + recordTarget_;
}

void App::finishRecording(bool atExit) {
  PathRecorder& recorder = scene_->poseSource().recorder();
  if (!recorder.finished()) return;
  const std::size_t samples = recorder.sampleCount();
  const bool full = recorder.overflowed();
  try {
    std::vector<std::string> inputs = scene_->request().bone.inputFiles();
    if (simulation::isPathCsv(scene_->request().path)) inputs.push_back(scene_->request().path);
    geometry::refuseOverwritingInputs({recordTarget_}, inputs);
    recorder.write(recordTarget_, scene_->periodS());
    panel_.recordMessage = "wrote " + std::to_string(samples) + " samples (" +
                           std::to_string(samples / 1000) + " s) to " + recordTarget_ +
                           (full ? " (the buffer was full: recording stopped)" : "");
  } catch (const InputError& e) {
    recorder.discard();
    if (atExit) throw;
    panel_.recordMessage = e.what();
  }
}

void App::openFile(const std::string& input) {
  if (input.empty()) return;
  // A mesh file's unit is asked each time: the panel shows the question, its answer opens it.
  if (fileNeedsUnits(input) && !panel_.openUnitMm) {
    panel_.askUnitsFor = input;
    return;
  }
  panel_.askUnitsFor.clear();
  const std::optional<double> unit = fileNeedsUnits(input) ? panel_.openUnitMm : std::nullopt;
  panel_.openUnitMm.reset();
  // BoneModel::open checks the unit and the voxel size.
  startLoading(requestForFile(scene_->request(), input, unit, panel_.openVoxelMm), input);
}

void App::startLoading(const LoadRequest& request, const std::string& name) {
  if (loading_.valid()) return;
  loadingName_ = name;
  panel_.loading = true;
  panel_.loadMessage = name;
  loading_ = std::async(std::launch::async, [request] { return Scene::load(request); });
}

void App::pollLoading() {
  if (!loading_.valid() || loading_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
    return;
  panel_.loading = false;
  try {
    std::unique_ptr<Scene> scene = loading_.get();
    installScene(std::move(scene), false);
    panel_.loadMessage.clear();
    glfwSetWindowTitle(window_.get(), ("osteon-viewer: " + scene_->request().bone.input).c_str());
  } catch (const InputError& e) {
    panel_.loadMessage = simulation::commandLineMessage(e);
  } catch (const std::bad_alloc&) {
    panel_.loadMessage = loadingName_ + ": out of memory (a larger --voxel-size needs less)";
  } catch (const std::exception& e) {
    panel_.loadMessage = loadingName_ + ": internal error: " + e.what();
  }
  loading_ = {};
}

}  // namespace osteon::viewer
