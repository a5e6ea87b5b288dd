// The ImGui panels: status line, |F| plot, views, camera, tool, crack metric, recording and
// file. They read a PanelModel the app fills each frame and leave requests in it; they never
// touch the scene themselves.
#pragma once

#include <optional>
#include <string>

#include "camera.h"
#include "metrics.h"
#include "options.h"
#include "osteon/simulation/exercise.h"
#include "osteon/simulation/score.h"

namespace osteon::viewer {

struct StatusNumbers {
  double hapticRateHz = 0.0;
  double stepP99Us = 0.0;       // collision step, p99 of the latest steps seen by the frames
  std::uint64_t overruns = 0;   // haptic + collision
  double remeshMs = 0.0;        // the latest updateSurface that had changes
  double uploadMs = 0.0;        // this frame's surface upload
  double naiveExtractMs = 0.0;  // the naive surface's latest whole extraction
  double frameMs = 0.0;
  double frameP99Ms = 0.0;
  std::size_t triangles = 0;
  bool surfaceReady = true;  // false while the first surface is extracted (drilling already runs)
  double removedVolumeMm3 = 0.0;
  double forceN = 0.0;
  double simTimeS = 0.0;
  int level = 0;       // finest level in contact
  double gapMm = 0.0;  // the proxy's tip to the commanded tip (0 under direct coupling)
};

// Where the tool is against an exercise's plan, each frame.
struct PlanReadouts {
  double entryDistanceMm = 0.0;  // the tip to the planned entry
  double angleErrorDeg = 0.0;    // the tool's axis to the planned axis
  double depthMm = 0.0;          // the tip past the entry along the planned axis
};

struct PanelModel {
  // What the app shows.
  std::string sceneName;
  bool followsPath = false;
  double pathDurationS = 0.0;
  bool proxyCoupling = false;
  bool calibrated = false;  // the calibrated force model (docs/feel.md) runs
  // Its heat model's: the peak temperature (°C) and the bone past the damage dose (mm3).
  double peakC = 37.0, damagedMm3 = 0.0;
  // The drill's settings: the panel edits them, the app hands them to the runtime.
  float rpm = 1000.0f;
  bool irrigation = false;
  bool ghost = false;  // the commanded pose is drawn beside the proxy
  bool drillOn = false;
  StatusNumbers status;
  const TimeSeries* force = nullptr;
  double maxForceN = 3.3;               // N_max, where the force is clamped
  double forceLimitN = 0.0;             // a task's force limit (0: none)
  int densityLow = 0, densityHigh = 1;  // the density ramp's ends (d)
  PixelCounts counts;
  bool countsValid = false;
  bool recording = false;
  std::size_t recordedSamples = 0;
  std::string recordMessage;  // the last write, or its failure
  bool loading = false;
  std::string loadMessage;      // the last load's failure, or what is loading
  std::string texturesMessage;  // why level/density views are unavailable ("" if they are)
  int hierarchyLevels = 0;
  std::string hierarchyMessage;

  // The exercise (null without one), the live readouts and the trial's score once scored.
  const simulation::Exercise* exercise = nullptr;
  const simulation::ExercisePlan* plan = nullptr;
  PlanReadouts readouts;
  std::optional<simulation::TrialScore> score;
  bool showPlan = true;

  // Settings the panels edit in place.
  View view = View::Shaded;
  SurfaceChoice method = SurfaceChoice::CrackFree;
  bool wire = false;
  bool showTool = true;
  CameraMode cameraMode = CameraMode::Orbit;
  bool pictureInPicture = false;
  bool liveMetric = true;
  int hierarchyLevel = 1;
  float hierarchyRadiusMm = 15.0f;
  char recordPath[1024] = {};
  char openPath[1024] = {};
  double openVoxelMm = 1.2;  // the base voxel size of the bone to open (a grid keeps its own)
  // A mesh file's unit, asked each time one is opened: the question's file, and the answer.
  std::string askUnitsFor;
  std::optional<double> openUnitMm;
  bool showHelp = false;     // the keys, over the view (F1, ?)
  bool confirmQuit = false;  // Esc asked: Enter quits, Esc stays

  // Requests for the app, cleared by it.
  bool toggleDrill = false, toggleRecord = false, frameBone = false, resetTool = false;
  bool focusTool = false, resetBone = false, quit = false, scoreTrial = false;
  std::optional<AxisView> axisView;
  bool open = false;
};

// Draws the panels when `ui`, and the floating windows (help, questions) whenever asked for
// (between ImGui::NewFrame and ImGui::Render).
void drawPanels(PanelModel& model, bool ui);

// panels_help.cpp: the help, the quit and unit questions; the force plot (newton axis, N_max
// and a task's limit as dashed lines) and the density ramp with its values.
void drawFloatingWindows(PanelModel& model);
void forcePlot(const TimeSeries& force, double maxForceN, double limitN);
void densityLegend(int lowD, int highD);
// The heat view's colour bar in °C, the peak and the bone past the damage dose.
void heatLegend(const PanelModel& m);
// panels_exercise.cpp: the exercise's instructions, plan and live readouts; the score.
void exerciseWindow(PanelModel& model);

}  // namespace osteon::viewer
