#include "app.h"

#include "gl_util.h"  // epoxy before GLFW

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <chrono>
#include <ctime>
#include <imgui.h>
#include <thread>

#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/image/image_writer.h"

namespace osteon::viewer {

namespace {

constexpr int kLiveMetricEveryFrames = 10;
// After a path's last pose, how long the loops keep going before a --frames run's last frame:
// the last steps' bricks reach the visual side within a few milliseconds.
constexpr double kPathSettleS = 0.25;

App* appOf(GLFWwindow* w) {
  return static_cast<App*>(glfwGetWindowUserPointer(w));
}

std::string timestampedRecordName() {
  const std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "osteon-path-%Y%m%d-%H%M%S.csv", std::localtime(&t));
  return buf;
}

}  // namespace

App::App(const ViewerOptions& options, std::unique_ptr<Scene> scene)
    : options_(options),
      window_(openWindow(options_.width, options_.height,
                         "osteon-viewer: " + scene->request().bone.input,
                         options_.frames > 0)) {  // a scripted run renders as fast as it can
  GLFWwindow* win = window_.get();
  glfwSetWindowUserPointer(win, this);
  glfwSetKeyCallback(win, [](GLFWwindow* w, int key, int, int action, int mods) {
    appOf(w)->onKey(key, action, mods);
  });
  glfwSetMouseButtonCallback(
      win, [](GLFWwindow* w, int b, int a, int m) { appOf(w)->onMouseButton(b, a, m); });
  glfwSetCursorPosCallback(win,
                           [](GLFWwindow* w, double x, double y) { appOf(w)->onCursor(x, y); });
  glfwSetScrollCallback(win, [](GLFWwindow* w, double, double dy) { appOf(w)->onScroll(dy); });
  glfwSetDropCallback(win, [](GLFWwindow* w, int n, const char** paths) {
    if (n > 0) appOf(w)->onDrop(paths[0]);
  });
  imgui_ = std::make_unique<ImGuiSession>(win);  // after the callbacks above, which it chains to

  renderer_ = std::make_unique<BoneRenderer>();
  overlay_ = std::make_unique<OverlayRenderer>();
  panel_.view = options_.view;
  panel_.method = options_.method;
  panel_.showTool = options_.tool;
  panel_.cameraMode = options_.cameraMode;
  panel_.pictureInPicture = options_.pictureInPicture;
  recordTarget_ = options_.record.empty() ? timestampedRecordName() : options_.record;
  std::snprintf(panel_.recordPath, sizeof panel_.recordPath, "%s", recordTarget_.c_str());
  std::snprintf(panel_.openPath, sizeof panel_.openPath, "%s", scene->request().bone.input.c_str());
  const simulation::BoneSource& bone = scene->request().bone;
  panel_.openVoxelMm =
      bone.voxelSizeMm.value_or(bone.defaultVoxelSizeMm.value_or(kDefaultVoxelSizeMm));
  if (options_.igtlPort) {
    igtl::ServerOptions so;
    so.port = *options_.igtlPort;
    so.bindAddress = options_.igtlBind;
    so.content = igtl::parseImageContent(options_.igtlContent);
    igtl_ = std::make_unique<igtl::Server>(so, scene->session().simulation().tool());
    std::fprintf(stderr, "osteon-viewer: serving OpenIGTLink on %s:%d\n", so.bindAddress.c_str(),
                 igtl_->port());
  }
  installScene(std::move(scene), !options_.record.empty());
  sound_ = std::make_unique<ViewerSound>(options_.mute);
}

void App::serveIgtl(bool last) {
  if (igtl_) igtl_->publish(scene_->live(), last);
}

App::~App() {
  if (loading_.valid()) loading_.wait();
  loading_ = {};
  scene_.reset();
  hierarchy_.clear();
  renderer_.reset();
  overlay_.reset();
  imgui_.reset();  // the window, then GLFW, go after it (members)
}

void App::installScene(std::unique_ptr<Scene> scene, bool recordFromStart) {
  if (scene_) {
    scene_->stop();
    finishRecording(false);
    scene_.reset();
  }
  scene_ = std::move(scene);
  ++report_.bonesLoaded;
  panel_.texturesMessage = renderer_->resetScene(scene_->live().visualGrid());
  hierarchy_.clear();
  naiveStale_ = true;
  force_.clear();
  camera_.setAxisView(options_.camera);
  camera_.frame(scene_->boundsMin(), scene_->boundsMax());
  if (options_.focusTool) camera_.setTarget(scene_->initialPose().tipMm);
  camera_.magnify(options_.zoom);
  aimScope();
  target_ = scene_->initialPose();
  drillOn_ = false;
  toolView_ = {};
  panel_.proxyCoupling = scene_->session().options().coupling == simulation::CouplingMode::Proxy;
  panel_.calibrated =
      scene_->session().options().forceModel == simulation::ForceModelKind::Calibrated;
  panel_.rpm = float(scene_->live().settings().rpm);
  panel_.irrigation = scene_->live().settings().irrigation;
  panel_.score.reset();
  panel_.sceneName = (scene_->exercise() ? "exercise " + scene_->exercise()->name + " | " : "") +
                     scene_->request().bone.input +
                     (scene_->path() ? " | path " + scene_->request().path : " | mouse");
  panel_.followsPath = scene_->path() != nullptr;
  panel_.pathDurationS = scene_->pathDurationS();
  if (recordFromStart) scene_->poseSource().recorder().start();
  lastRateS_ = glfwGetTime();
  lastRateSteps_ = 0;
  scene_->start();
}

int App::run() {
  while (true) {
    if (options_.frames > 0 && frame_ >= std::size_t(options_.frames)) break;
    glfwPollEvents();
    pollLoading();
    handleRequests();
    // Closed by hand (Esc, the window's button): one more frame, the last, so --screenshot and
    // the metric still see what the hand left.
    const bool closing = glfwWindowShouldClose(window_.get());
    const bool last =
        closing || (options_.frames > 0 && frame_ + 1 == std::size_t(options_.frames));
    if (last && !closing) waitForPath();
    const Clock::time_point start = Clock::now();
    frame(last);
    const double ms = msSince(start) - report_.screenshotMs;  // writing the PNG is not rendering
    frameMs_.add(ms);
    lastFrameMs_ = ms;
    ++frame_;
    if (closing) break;
  }
  finishReport();
  return kExitOk;
}

void App::waitForPath() {
  if (!scene_->path()) return;
  const double needS = scene_->pathDurationS() + kPathSettleS;
  const double giveUpS = glfwGetTime() + needS + 30.0;
  while (scene_->live().display().tS < needS && glfwGetTime() < giveUpS &&
         !glfwWindowShouldClose(window_.get())) {
    glfwPollEvents();
    // Keeps the ring drained; the changes add up for the frame.
    if (scene_->live().updateSurface() > 0.0) naiveStale_ = true;
    serveIgtl(false);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  waitedForPath_ = true;
}

void App::frame(bool last) {
  glfwGetFramebufferSize(window_.get(), &width_, &height_);
  simulation::LiveRuntime& live = scene_->live();
  updateSurfaces();
  const simulation::DisplayState& d = live.display();
  live.setSettings({double(panel_.rpm), panel_.irrigation});  // the panel's, next period on
  if (const simulation::ThermalModel* heat = scene_->session().thermal()) {
    // This thread diffuses it (LiveRuntime::updateSurface): the consumer side may be read.
    panel_.peakC = heat->peakC();
    // The bone left past the dose: a scan of the heated cells, twice a second.
    if (frame_ % 30 == 0 || last) panel_.damagedMm3 = heat->damagedBoneVolumeMm3(live.visualGrid());
    if (panel_.view == View::Heat) renderer_->heat().update(*heat);
  }
  sound_->feed(d);
  if (panel_.view == View::Levels)
    renderer_->textures().updateLevels(d.refined.data(), d.refinedCount, d.refinedDepth);
  force_.add(glfwGetTime(), float(d.contact.magnitudeN));
  if (panel_.view == View::Hierarchy) {
    try {
      hierarchy_.poll();
      hierarchy_.maybeRebuild(live.visualGrid(), glfwGetTime(), lastView_ != View::Hierarchy);
    } catch (const std::exception& e) {
      panel_.hierarchyMessage = e.what();
    }
  }
  lastView_ = panel_.view;

  updateCameras();
  const FrameCamera camera = cameraFor(panel_.cameraMode, width_, height_);
  glViewport(0, 0, width_, height_);
  if (panel_.view == View::Cracks || panel_.cameraMode == CameraMode::Scope) {
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  } else {
    glClearColor(0.13f, 0.14f, 0.16f, 1.0f);
  }
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  drawBone(camera);
  // The metric reads the bone alone, before the tool and the panels are drawn.
  if (last ||
      (panel_.view == View::Cracks && panel_.liveMetric && frame_ % kLiveMetricEveryFrames == 0))
    readMetric();

  const simulation::ToolPose pose = d.tS >= 0.0 ? d.pose : scene_->initialPose();
  const simulation::ToolPose commanded = d.tS >= 0.0 ? d.commanded : pose;
  // The depth walk is for the report only.
  toolView_.add(scene_->tool(), pose, commanded, d.gapMm,
                options_.json ? &live.visualGrid() : nullptr);
  panel_.ghost = toolView_.ghostLast;
  updateExercise(pose);
  drawOverlays(camera, pose, commanded);
  if (panel_.cameraMode == CameraMode::Scope)
    overlay_->drawFieldMask(double(std::max(width_, 1)) / double(std::max(height_, 1)));
  if (panel_.pictureInPicture) drawPictureInPicture(pose, commanded);

  fillStatus(lastFrameMs_);
  if (panel_.showHelp) ++report_.helpFrames;
  const bool floating = panel_.showHelp || panel_.confirmQuit || !panel_.askUnitsFor.empty() ||
                        panel_.plan != nullptr;
  if (options_.ui || floating) {
    panel_.drillOn = drillOn_;
    panel_.maxForceN = scene_->tool().maxForceN;
    panel_.densityLow = renderer_->textures().densityLow();
    panel_.densityHigh = renderer_->textures().densityHigh();
    panel_.force = &force_;
    panel_.hierarchyLevels = hierarchy_.levelCount();
    PathRecorder& recorder = scene_->poseSource().recorder();
    panel_.recording = recorder.recording();
    panel_.recordedSamples = recorder.sampleCount();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    drawPanels(panel_, options_.ui);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  }
  if (last && !options_.screenshot.empty()) writeScreenshot();
  glfwSwapBuffers(window_.get());
}

// The visual side's update and the upload of what changed (the naive view extracts whole).
void App::updateSurfaces() {
  simulation::LiveRuntime& live = scene_->live();
  const double remeshMs = live.updateSurface();
  serveIgtl(false);
  if (remeshMs > 0.0) {
    panel_.status.remeshMs = remeshMs;
    naiveStale_ = true;
  }
  const simulation::SurfaceChanges delta = live.takeSurfaceChanges();
  const Clock::time_point start = Clock::now();
  renderer_->applyChanges(delta);
  renderer_->textures().updateDensity(live.visualGrid(), delta);
  double uploadMs = msSince(start);
  if (panel_.method == SurfaceChoice::Naive && naiveStale_) {
    geometry::SurfaceOptions naive = scene_->session().options().surface;
    naive.method = geometry::SurfaceMethod::Naive;
    const Clock::time_point extract = Clock::now();
    const geometry::SurfaceMesh mesh = geometry::extractSurface(live.visualGrid(), naive);
    panel_.status.naiveExtractMs = msSince(extract);
    const Clock::time_point upload = Clock::now();
    renderer_->uploadWhole(mesh);
    uploadMs += msSince(upload);
    naiveStale_ = false;
  }
  panel_.status.uploadMs = uploadMs;
  uploadMs_.add(uploadMs);
}

void App::readMetric() {
  std::vector<std::uint8_t> pixels(std::size_t(width_) * std::size_t(height_) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  panel_.counts = countCrackPixels(pixels.data(), width_, height_);
  panel_.countsValid = true;
}

void App::writeScreenshot() {
  const Clock::time_point start = Clock::now();
  std::vector<std::uint8_t> pixels(std::size_t(width_) * std::size_t(height_) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  flipRows(pixels, width_, height_, 3);
  const std::string error =
      image::writeImageU8(options_.screenshot, width_, height_, 3, pixels.data());
  if (!error.empty()) throw InputError(options_.screenshot + ": " + error);
  report_.screenshotMs = msSince(start);
}

void App::fillStatus(double frameMs) {
  const simulation::LiveStats st = scene_->live().stats();
  const double now = glfwGetTime();
  StatusNumbers& s = panel_.status;
  if (now - lastRateS_ >= 0.5) {
    s.hapticRateHz =
        double(st.hapticSteps - std::min(st.hapticSteps, lastRateSteps_)) / (now - lastRateS_);
    lastRateS_ = now;
    lastRateSteps_ = st.hapticSteps;
  }
  stepUs_.add(st.collisionStepUsLast);
  s.stepP99Us = stepUs_.recentP99();
  s.overruns = st.hapticOverruns + st.collisionOverruns;
  s.triangles = renderer_->triangles(panel_.method);
  s.surfaceReady = scene_->live().stats().surfaceBuildMs > 0.0;
  const simulation::DisplayState& d = scene_->live().display();
  s.removedVolumeMm3 = d.removedVolumeMm3;
  s.forceN = d.contact.magnitudeN;
  s.level = d.contact.level;
  s.gapMm = d.gapMm;
  s.simTimeS = d.tS;
  s.frameMs = frameMs;
  s.frameP99Ms = frameMs_.recentP99();
}

void App::finishReport() {
  const simulation::RuntimeResult result = scene_->stop();
  if (scene_->exercise()) {
    scoreTrial();  // scored now if the trial had not ended (and sent to --igtl's clients)
    report_.exercise = scene_->exercise()->name;
    report_.scoreJson = simulation::scoreJsonText(*panel_.score);
  }
  ViewerReport& r = report_;
  sound_->report(r);
  const simulation::SessionOptions& so = scene_->session().options();
  r.forceModel = simulation::forceModelKindName(so.forceModel);
  r.rpm = double(panel_.rpm);
  r.irrigation = panel_.irrigation;
  if (simulation::ThermalModel* heat = scene_->session().thermal()) {
    r.peakTemperatureC = heat->peakC();
    r.damagedBoneMm3 = heat->damagedBoneVolumeMm3(scene_->live().visualGrid());
  }
  if (igtl_) {
    serveIgtl(true);
    igtlStats = igtl_->stop();
    r.igtlServed = true;
    r.igtlAddress = options_.igtlBind + ":" + std::to_string(igtl_->port());
    r.igtlClients = igtlStats->clients;
    r.igtlMessages = igtlStats->messagesSent;
    r.igtlBytes = igtlStats->bytesSent;
    r.igtlDropped = igtlStats->dropped;
    r.igtlVolumes = igtlStats->volumesSent;
    r.igtlStrings = igtlStats->strings;
    r.igtlRejected = igtlStats->rejected;
  }
  r.recordedSamples = scene_->poseSource().recorder().sampleCount();
  finishRecording(true);
  r.input = scene_->request().bone.input;
  r.view = viewName(panel_.view);
  r.method = surfaceChoiceName(panel_.method);
  r.path = scene_->request().path;
  r.width = width_;
  r.height = height_;
  r.frames = frame_;
  r.frameMs = frameMs_.percentiles();
  r.uploadMs = uploadMs_.percentiles();
  r.remeshMs = result.stats.remeshMs;
  r.triangles = renderer_->triangles(panel_.method);
  r.redPixels = panel_.counts.red;
  r.redSilhouettePixels = panel_.counts.redSilhouette;
  r.whitePixels = panel_.counts.white;
  r.bonePixels = panel_.counts.foreground();
  r.boneCentroid[0] = panel_.counts.centroidX;
  r.boneCentroid[1] = panel_.counts.centroidY;
  r.levelMinus1Pixels = panel_.counts.levelMinus1;
  r.levelMinus2Pixels = panel_.counts.levelMinus2;
  r.hapticSteps = result.stats.hapticSteps;
  r.hapticOverruns = result.stats.hapticOverruns;
  r.collisionSteps = result.stats.collisionSteps;
  r.collisionOverruns = result.stats.collisionOverruns;
  r.realtimePriority = result.stats.realtimeGranted;
  r.removedVolumeMm3 = result.run.summary.removedVolumeMm3;
  r.maxForceN = result.run.summary.maxForceN;
  r.coupling = simulation::couplingModeName(result.run.summary.coupling);
  r.maxGapMm = result.run.summary.maxGapMm;
  r.clampSteps = result.run.summary.clampSteps;
  r.gapMm = toolView_.gapLastMm;
  r.ghost = toolView_.ghostLast;
  r.ghostFrames = toolView_.ghostFrames;
  r.proxyDepthMm = toolView_.maxProxyDepthMm;
  r.commandedDepthMm = toolView_.maxCommandedDepthMm;
  for (int i = scene_->tool().partCount - 1; i >= 0; --i) {
    const simulation::ToolPart& part = scene_->tool().parts[std::size_t(i)];
    if (part.cuts)
      r.toolCushionMm = part.outerRadiusMm - part.innerRadiusMm;  // the first cutting part's
  }
  if (options_.json) {
    // The drilled bone's surface as the window shows it: a sealed cavity is a second component.
    const geometry::MeshTopology topology =
        geometry::analyzeTopology(scene_->live().visualSurface().mesh().toTriangleMesh());
    r.surfaceComponents = topology.components;
    r.surfaceBorderEdges = topology.borderEdges;
  }
  r.pathDurationS = scene_->pathDurationS();
  r.waitedForPath = waitedForPath_;
  r.loadMs = scene_->loadMs();
  r.setup = scene_->session().setupTimings();
  r.setup.surfaceMs = scene_->live().stats().surfaceBuildMs;  // the visual side's, beside the steps
  r.setup.totalMs =
      scene_->loadMs();  // the scene's whole set-up: session, path and runtime started
  r.peakRssMb = peakRssMb();
  r.screenshot = options_.screenshot;
  r.record = options_.record;
  r.camera = cameraModeName(panel_.cameraMode);
  r.pictureInPicture = panel_.pictureInPicture;
  r.help = panel_.showHelp;
  r.lensRotationDeg = glm::degrees(scope_.lensRotation());
}

}  // namespace osteon::viewer
