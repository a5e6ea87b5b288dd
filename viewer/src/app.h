// The viewer's window and loop: GLFW (X11) with an OpenGL 3.3 core context, Dear ImGui, the
// scene's live runtime, and one frame at a time: the visual side's surface update, the
// incremental upload, the draw, the metric, the panels.
#pragma once

#include <cstdio>
#include <future>
#include <memory>
#include <optional>
#include <string>

#include "camera.h"
#include "hierarchy_view.h"
#include "metrics.h"
#include "options.h"
#include "osteon/igtl/server.h"
#include "overlay.h"
#include "panels.h"
#include "renderer.h"
#include "report.h"
#include "scene.h"
#include "scope.h"
#include "sound.h"
#include "tool_view.h"
#include "window.h"

namespace osteon::viewer {

class App {
 public:
  // Its clients' counters, when --igtl serves the session.
  std::optional<igtl::ServerStats> igtlStats;

  // Opens the window (throws WindowError); the scene is loaded and not yet started.
  App(const ViewerOptions& options, std::unique_ptr<Scene> scene);
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  // Runs until the window closes or --frames are drawn; returns the exit code. Fills report().
  int run();
  const ViewerReport& report() const { return report_; }

  // ---- input (input.cpp), called from GLFW's callbacks ----
  void onKey(int key, int action, int mods);
  void onCommandKey(int key);
  void onMouseButton(int button, int action, int mods);
  void onCursor(double x, double y);
  void onScroll(double dy);
  void onDrop(const std::string& path);

 private:
  void installScene(std::unique_ptr<Scene> scene, bool recordFromStart);
  void frame(bool last);
  void updateSurfaces();
  // The visual side's state to the OpenIGTLink server, if --igtl (last: after the loops stop).
  void serveIgtl(bool last);
  void readMetric();
  void writeScreenshot();
  void waitForPath();
  void pollLoading();
  // Opens a file from the window (asking a mesh file's unit first).
  void openFile(const std::string& input);
  void startLoading(const LoadRequest& request, const std::string& name);
  void handleRequests();
  void moveToolAlong(const glm::dvec3& direction, double mm);
  void toggleRecording();
  // Writes a finished recording; at exit a failure throws (exit 2), otherwise the panel says it.
  void finishRecording(bool atExit);
  void publishTarget();
  void moveToolInView(double dxPixels, double dyPixels);
  void turnTool(double dxPixels, double dyPixels);
  void fillStatus(double frameMs);
  void finishReport();

  // ---- cameras and what each view draws (views.cpp) ----
  // The arthroscope at its portal, looking at the work site from across the tool.
  void aimScope();
  // The scope's device, and the follow camera's target, each frame.
  void updateCameras();
  FrameCamera cameraFor(CameraMode mode, int width, int height) const;
  // The main view's axes, for the mouse tool and zoom (eye, forward, right, up, vertical fov).
  ViewBasis viewBasis() const;
  void drawBone(const FrameCamera& camera);
  void drawOverlays(const FrameCamera& camera, const simulation::ToolPose& pose,
                    const simulation::ToolPose& commanded);
  // The second view in the top right corner.
  void drawPictureInPicture(const simulation::ToolPose& pose,
                            const simulation::ToolPose& commanded);
  void zoomAtCursor(double steps);
  void focusOnTool();
  void cycleCamera();

  // ---- an exercise (exercise_view.cpp) ----
  // The readouts against the plan; a path's trial is scored once the path has ended.
  void updateExercise(const simulation::ToolPose& pose);
  // The plan over the bone: the entry marker, the axis, the depth ring; the head and the entry.
  void drawPlan(const FrameCamera& camera);
  void drawHeadAndEntry(const FrameCamera& camera);
  // Stops the loops and scores the trial (once).
  void scoreTrial();
  ViewerOptions options_;
  // Released last, in this reverse order, after every GL object below (window.h).
  GlfwLibrary glfw_;
  GlfwWindowPtr window_;
  std::unique_ptr<ImGuiSession> imgui_;
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<BoneRenderer> renderer_;
  std::unique_ptr<OverlayRenderer> overlay_;
  OrbitCamera camera_;
  Arthroscope scope_;
  OrbitCamera follow_;
  std::int64_t scopeKnob0_ = 0;  // the scope device's knob at its first sample
  bool scopeKnobSeen_ = false;
  HierarchyView hierarchy_;
  PanelModel panel_;
  TimeSeries force_{5.0};
  FrameSeries frameMs_, uploadMs_, stepUs_;
  std::future<std::unique_ptr<Scene>> loading_;
  std::string loadingName_;

  // The mouse's tool target (render thread's copy; the pose source gets it through a triple
  // buffer).
  simulation::ToolPose target_;
  bool drillOn_ = false;
  std::string recordTarget_;  // where the running recording goes

  // Input state.
  double cursorX_ = 0.0, cursorY_ = 0.0;
  bool leftDown_ = false, middleDown_ = false, rightDown_ = false;
  int mods_ = 0;
  int width_ = 0, height_ = 0;  // framebuffer

  // Per-frame state.
  std::size_t frame_ = 0;
  double lastFrameMs_ = 0.0;
  bool naiveStale_ = true;
  View lastView_ = View::Shaded;
  double lastRateS_ = 0.0;
  std::uint64_t lastRateSteps_ = 0;
  bool waitedForPath_ = false;
  ToolViewTally toolView_;  // the ghost and how deep the proxy and the hand reached, per frame
  ViewerReport report_;
  std::unique_ptr<igtl::Server> igtl_;  // --igtl
  std::unique_ptr<ViewerSound> sound_;
};

}  // namespace osteon::viewer
