#include "options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/simulation/exercise.h"
#include "osteon/simulation/path.h"

namespace osteon::viewer {

namespace {

constexpr const char* kViewNames[] = {"shaded",    "cracks",    "levels", "density",
                                      "hierarchy", "wireframe", "heat"};

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// A positive integer of at most 5 digits, the whole text.
bool parseSide(const std::string& text, int& value) {
  if (text.empty() || text.size() > 5) return false;
  for (const char c : text) {
    if (c < '0' || c > '9') return false;
  }
  value = std::stoi(text);
  return true;
}

}  // namespace

const char* viewName(View view) {
  return kViewNames[int(view)];
}

View parseView(const std::string& text) {
  for (int i = 0; i < int(std::size(kViewNames)); ++i) {
    if (text == kViewNames[i]) return View(i);
  }
  throw InputError(
      "--view " + text +
      ": unknown view (expected shaded, cracks, levels, density, hierarchy or wireframe)");
}

const char* surfaceChoiceName(SurfaceChoice method) {
  return method == SurfaceChoice::Naive ? "naive" : "crackfree";
}

SurfaceChoice parseSurfaceChoice(const std::string& text) {
  if (text == "crackfree") return SurfaceChoice::CrackFree;
  if (text == "naive") return SurfaceChoice::Naive;
  throw InputError("--method " + text + ": unknown method (expected crackfree or naive)");
}

AxisView parseAxisView(const std::string& text) {
  for (int i = 0; i < 6; ++i) {
    if (text == axisViewName(AxisView(i))) return AxisView(i);
  }
  throw InputError(
      "--camera " + text +
      ": unknown view (expected anterior, posterior, right, left, superior or inferior)");
}

const char* cameraModeName(CameraMode mode) {
  switch (mode) {
    case CameraMode::Orbit:
      return "orbit";
    case CameraMode::Scope:
      return "scope";
    case CameraMode::Follow:
      return "follow";
  }
  return "?";
}

void parseCamera(const std::string& text, AxisView& axis, CameraMode& mode) {
  if (text == "scope" || text == "follow") {
    mode = text == "scope" ? CameraMode::Scope : CameraMode::Follow;
    return;
  }
  for (int i = 0; i < 6; ++i) {
    if (text == axisViewName(AxisView(i))) {
      axis = AxisView(i);
      mode = CameraMode::Orbit;
      return;
    }
  }
  throw InputError("--camera " + text +
                   ": unknown view (expected anterior, posterior, right, left, superior, "
                   "inferior, scope or follow)");
}

bool isExercise(const std::string& input) {
  const std::vector<std::string> names = simulation::builtInExerciseNames();
  return lowerExtension(input) == ".json" ||
         std::find(names.begin(), names.end(), input) != names.end();
}

bool fileNeedsUnits(const std::string& input) {
  const std::string ext = lowerExtension(input);
  return ext == ".stl" || ext == ".obj" || ext == ".ply" || ext == ".off";
}

LoadRequest requestForFile(const LoadRequest& current, const std::string& input,
                           std::optional<double> scaleToMm, double voxelMm) {
  LoadRequest request;
  request.levels = current.levels;
  request.tool = current.tool;
  request.coupling = current.coupling;
  request.forceModel = current.forceModel;
  request.settings = current.settings;
  request.device = current.device;
  request.scopeDevice = current.scopeDevice;
  if (isExercise(input)) {
    request.exercise = input;  // the exercise names its own bone
    return request;
  }
  request.bone.input = input;
  request.bone.scale = scaleToMm;
  request.bone.defaultVoxelSizeMm = voxelMm;  // a grid keeps its own
  return request;
}

void parseWindowSize(const std::string& text, int& width, int& height) {
  const std::size_t x = text.find_first_of("xX");
  int w = 0, h = 0;
  if (x == std::string::npos || !parseSide(text.substr(0, x), w) ||
      !parseSide(text.substr(x + 1), h)) {
    throw InputError("--size " + text + ": must be WIDTHxHEIGHT in pixels, e.g. 1280x800");
  }
  if (w < 64 || h < 64 || w > 8192 || h > 8192) {
    throw InputError("--size " + text + ": each side must be 64..8192 pixels");
  }
  width = w;
  height = h;
}

void validateOptions(const ViewerOptions& options) {
  const LoadRequest& load = options.load;
  load.bone.check();
  if (load.levels < 0 || load.levels > 2) {
    throw InputError("--levels " + std::to_string(load.levels) + ": must be 0, 1 or 2");
  }
  if (!(std::isfinite(options.zoom) && options.zoom >= 0.01 && options.zoom <= 100.0)) {
    std::ostringstream s;
    s << "--zoom " << options.zoom << ": must be 0.01..100";
    throw InputError(s.str());
  }
  if (options.frames < 0)
    throw InputError("--frames " + std::to_string(options.frames) + ": must be 0 or more");
  if (!load.device.empty() && !load.path.empty()) {
    throw InputError("--device " + load.device + ": give a device or a --path, not both");
  }
  if (!load.device.empty() && !options.record.empty()) {
    throw InputError("--record " + options.record +
                     ": with --device, record with `osteon drill --device " + load.device +
                     " --record` (the viewer records the mouse or a path)");
  }
  for (const std::string* out : {&options.screenshot, &options.record}) {
    if (out->empty()) continue;
    const std::filesystem::path folder = std::filesystem::path(*out).parent_path();
    if (!folder.empty() && !std::filesystem::is_directory(folder)) {
      throw InputError(*out + ": the folder " + folder.string() + " does not exist");
    }
  }
  if (!options.screenshot.empty() && lowerExtension(options.screenshot) != ".png") {
    throw InputError("--screenshot " + options.screenshot + ": must be a .png file");
  }
  if (!options.record.empty() && !simulation::isPathCsv(options.record)) {
    throw InputError("--record " + options.record + ": must be a .csv file");
  }
  std::vector<std::string> inputs = load.bone.inputFiles();
  if (simulation::isPathCsv(load.path)) inputs.push_back(load.path);
  std::vector<std::string> outputs;
  for (const std::string& out : {options.screenshot, options.record}) {
    if (!out.empty()) outputs.push_back(out);
  }
  geometry::refuseOverwritingInputs(outputs, inputs);
  if (!options.screenshot.empty() && !options.record.empty() &&
      std::filesystem::absolute(options.screenshot) == std::filesystem::absolute(options.record)) {
    throw InputError(options.record + ": --screenshot and --record name the same file");
  }
}

}  // namespace osteon::viewer
