// What `osteon-viewer --json` prints on exit: one JSON object (report.cpp is the only
// translation unit that includes nlohmann/json).
#pragma once

#include <cstdint>
#include <string>

#include "osteon/simulation/runner.h"
#include "osteon/simulation/session.h"

namespace osteon::viewer {

struct ViewerReport {
  std::string input, view, method, path;
  int width = 0, height = 0;
  std::size_t frames = 0;
  simulation::Percentiles frameMs;   // render work per frame (the wait for a path excluded)
  simulation::Percentiles uploadMs;  // surface changes to the GPU per frame
  simulation::Percentiles remeshMs;  // updateSurface per frame that had changes
  std::size_t triangles = 0;         // of the surface drawn on the last frame
  std::uint64_t redPixels = 0, redSilhouettePixels = 0, whitePixels = 0;  // last frame, bone only
  std::uint64_t bonePixels = 0;         // not background (crack view: red + white)
  double boneCentroid[2] = {0.0, 0.0};  // fractions of the frame, y from the top
  std::uint64_t levelMinus1Pixels = 0, levelMinus2Pixels = 0;  // level view colours
  std::uint64_t hapticSteps = 0, hapticOverruns = 0;
  std::uint64_t collisionSteps = 0, collisionOverruns = 0;
  bool realtimePriority = false;
  double removedVolumeMm3 = 0.0;
  double maxForceN = 0.0;
  std::string coupling;          // proxy or direct
  double maxGapMm = 0.0;         // the run's largest proxy-to-commanded tip distance
  std::uint64_t clampSteps = 0;  // haptic steps whose force was at N_max
  double gapMm = 0.0;            // on the last frame
  bool ghost = false;            // the commanded pose drawn as a ghost on the last frame
  std::uint64_t ghostFrames = 0;
  double proxyDepthMm = 0.0;  // deepest the drawn tool sat in bone (boneDepthMm), over the frames
  double commandedDepthMm = 0.0;  // the same for the commanded pose
  double toolCushionMm = 0.0;     // the cutting part's shell: outer minus inner radius
  std::size_t surfaceComponents = 0, surfaceBorderEdges = 0;  // the visual surface at exit
  double pathDurationS = 0.0;
  bool waitedForPath = false;
  double loadMs = 0.0;
  simulation::SetupTimings
      setup;               // the session's stages; totalMs is loadMs (the scene's whole set-up)
  double peakRssMb = 0.0;  // the process's peak resident set when the report is made
  std::string screenshot, record;
  double screenshotMs = 0.0;  // read back, flipped and written (not in frameMs)
  std::size_t recordedSamples = 0;
  std::string camera;             // the main view's camera at exit: orbit, scope or follow
  bool pictureInPicture = false;  // at exit
  std::uint64_t helpFrames = 0;   // frames drawn with the key help shown
  bool help = false;              // shown on the last frame
  std::size_t bonesLoaded = 0;    // the first, then each reset or opened file
  double lensRotationDeg = 0.0;   // the arthroscope's lens at exit
  std::string exercise;           // its name ("" without one)
  std::string scoreJson;          // the trial's score (scoreJsonText; "" when not scored)
  // The force model and the drill at exit (docs/feel.md); the heat model's peak and damage.
  std::string forceModel = "seed";
  double rpm = 0.0;
  bool irrigation = false;
  double peakTemperatureC = 37.0, damagedBoneMm3 = 0.0;
  // --igtl: the server's counters at exit (igtl::ServerStats); served false without it.
  bool igtlServed = false;
  std::string igtlAddress;
  std::uint64_t igtlClients = 0, igtlMessages = 0, igtlBytes = 0, igtlDropped = 0;
  std::uint64_t igtlVolumes = 0, igtlStrings = 0, igtlRejected = 0;
  // The drill's sound (sound.h): an audio device opened, muted at exit, frames fed and dropped.
  bool soundDevice = false, soundMuted = false;
  std::uint64_t soundFrames = 0, soundDropped = 0;
};

std::string reportJson(const ViewerReport& report);

}  // namespace osteon::viewer
