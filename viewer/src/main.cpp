// `osteon-viewer`: parses the options (CLI11 lives here alone), loads the bone, then opens the
// window. Every refusal of the input comes before a window opens; errors are one line on stderr
// and the exit codes are the CLI's: 0 success, 2 bad input or no window, 3 an internal error.
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "app.h"
#include "options.h"
#include "osteon/core/error.h"
#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/path.h"
#include "report.h"
#include "scene.h"

namespace {

namespace viewer = osteon::viewer;
using osteon::kExitBadInput;
using osteon::kExitInternal;
using osteon::kExitOk;

std::string oneLine(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

int fail(int code, const std::string& message) {
  std::cerr << (code == kExitInternal ? "osteon-viewer: internal error: "
                                      : "osteon-viewer: error: ")
            << oneLine(message) << "\n";
  return code;
}

// What a volume means and which part of it is loaded: the flags of osteon's own commands, turned
// into VolumeOptions (the crop text parsed by the library, its errors named by flag).
struct VolumeFlags {
  std::optional<std::uint64_t> label;
  std::optional<double> isoValue;
  bool allowOutsideData = false;
  std::optional<std::string> crop;
  std::optional<std::uint64_t> cropToLabel;
  double cropMarginMm = 10.0;
  std::string series;
};

void addVolumeFlags(CLI::App& app, VolumeFlags& f) {
  // CLI11 reads "-1" into an unsigned as 2^64 - 1: a label is refused rather than wrapped.
  const CLI::Validator nonNegative(
      [](std::string& text) {
        const std::size_t first = text.find_first_not_of(" \t");
        return first != std::string::npos && text[first] == '-'
                   ? "must be a non-negative integer, not " + text
                   : std::string();
      },
      "LABEL");
  app.add_option(
         "--label", f.label,
         "Label maps: the bone label, 0 .. 2^64-1 (default: every voxel but the background)")
      ->check(nonNegative);
  app.add_option(
      "--iso", f.isoValue,
      "CT volumes: the bone threshold in HU (default 300); other volumes: in their own units");
  app.add_flag(
      "--allow-outside-data", f.allowOutsideData,
      "NRRD and MetaImage volumes: read a data file outside the header's folder (refused by "
      "default)");
  app.add_option("--series", f.series,
                 "DICOM folders: the Series Instance UID to read (default: the series with most "
                 "slices)");
  app.add_option("--crop", f.crop, "Volumes: load only X0:X1,Y0:Y1,Z0:Z1 (LPS mm)");
  app.add_option("--crop-to-label", f.cropToLabel,
                 "Label maps: load only the box of this label, grown by --crop-margin")
      ->check(nonNegative);
  app.add_option("--crop-margin", f.cropMarginMm,
                 "mm added on every side of --crop-to-label's box (default 10)");
}

void applyVolumeFlags(const VolumeFlags& f, osteon::geometry::VolumeOptions& volume) {
  volume.label = f.label;
  volume.isoValue = f.isoValue;
  volume.allowOutsideData = f.allowOutsideData;
  volume.series = f.series;
  if (f.crop) volume.cropMm = osteon::simulation::parseCropMm(*f.crop);
  volume.cropToLabel = f.cropToLabel;
  volume.cropMarginMm = f.cropMarginMm;
}

// The command line as typed, before it is checked and turned into ViewerOptions.
struct CommandLine {
  std::string input = "default";
  std::optional<std::string> units;
  std::optional<double> scale;
  std::optional<double> voxelSize;
  VolumeFlags volume;
  int levels = 2;
  std::string forceModel;
  std::optional<double> rpm;
  bool irrigation = false;
  std::string tool = "drill", path, device, coupling, view = "shaded", method = "crackfree",
              size = "1280x800", camera = "anterior", focus = "bone";
  std::string scopeDevice, exercise, up;
  bool noUi = false, noTool = false;
};

// The bone: the input, its units, voxel size and meaning.
void addBoneOptions(CLI::App& app, CommandLine& c) {
  app.add_option("MESH", c.input,
                 std::string("Mesh file (.stl .obj .ply .off), 'default' (built-in humerus), or a "
                             "volume: an osteon grid, a label map, a CT or a scalar volume (") +
                     osteon::simulation::kVolumeFormsText + ")")
      ->default_val("default");
  addVolumeFlags(app, c.volume);
  CLI::Option* u =
      app.add_option("--units", c.units, "Unit of the mesh file's coordinates: mm, cm, m or in");
  CLI::Option* s =
      app.add_option("--scale", c.scale, "Multiply coordinates by S to get millimetres");
  u->excludes(s);
  app.add_option("--up", c.up,
                 "Which way is up, from the shaft to the humeral head: x, y, z, -x, -y or -z "
                 "(default: found from the bone)");
  app.add_option("--voxel-size", c.voxelSize,
                 "Base voxel edge in mm (default 1.2 for a mesh; a grid has its own)");
  app.add_option("--levels", c.levels,
                 "0: static voxels; 1 or 2: refine near the tool (VS/2, VS/4)")
      ->default_val(2);
}

// The tool and what drives it.
void addToolOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--tool", c.tool, "drill, burr or shaver")->default_val("drill");
  app.add_option("--path", c.path,
                 "portal-5, portal-7 or PATH.csv: play a path instead of the mouse (with "
                 "--exercise, plan plays its ideal path)");
  app.add_option("--exercise", c.exercise,
                 "An exercise, built in (anchor-5, anchor-7) or a JSON file: its bone and tool, "
                 "its plan drawn over the bone, live readouts and a score at the end");
  app.add_option("--coupling", c.coupling,
                 "proxy: bone stops the tool, a spring joins it to the hand (default, but for "
                 "portal paths); direct");
  app.add_option("--force-model", c.forceModel,
                 "seed (the paper's eq. 2) or calibrated (thrust fitted to published drilling "
                 "data; the default when the mouse or a device drives)");
  app.add_option("--rpm", c.rpm, "The drill's speed at start, revolutions per minute (1000)");
  app.add_flag("--irrigation", c.irrigation, "Start with saline irrigation on");
  app.add_option(
      "--device", c.device,
      "Drive the tool from a device (spacemouse, serial:PORT, touch, replay:LOG.csv, ...)");
}

// What is shown, and the run's outputs.
void addDisplayOptions(CLI::App& app, CommandLine& c, viewer::ViewerOptions& options) {
  app.add_option("--frames", options.frames,
                 "Render N frames and exit (with --path, the last waits for its end)");
  app.add_option("--screenshot", options.screenshot, "Write the last frame to this PNG");
  app.add_option("--view", c.view, "shaded, cracks, levels, density, hierarchy or wireframe")
      ->default_val("shaded");
  app.add_option("--method", c.method,
                 "The surface drawn: crackfree (live, incremental) or naive (seed's MC, whole)")
      ->default_val("crackfree");
  app.add_option("--camera", c.camera,
                 "Start view: anterior (looking along +y, framed on the bone), posterior, right, "
                 "left, superior, inferior; scope (the 30 degree arthroscope at its portal) or "
                 "follow (a camera on the tool)")
      ->default_val("anterior");
  app.add_option("--zoom", options.zoom, "Magnify the start view by this factor")->default_val(1.0);
  app.add_option("--focus", c.focus, "Centre of the start view: bone, or tool (its first pose)")
      ->default_val("bone");
  app.add_option("--size", c.size, "Window size WIDTHxHEIGHT in pixels")->default_val("1280x800");
  app.add_option("--record", options.record,
                 "Record the tool's path (1 kHz) from the start to exit into this CSV");
  app.add_flag("--pip", options.pictureInPicture,
               "Picture-in-picture: the arthroscope in the corner (the orbit view when the "
               "main view is the scope); P toggles");
  app.add_option("--scope-device", c.scopeDevice,
                 "The arthroscope's pose (and its knob: the lens rotation) from a second device");
  app.add_flag("--json", options.json, "Print one JSON object on stdout at exit");
  app.add_option("--igtl", options.igtlPort,
                 "Serve the session over OpenIGTLink on this TCP port (3D Slicer: 18944)");
  app.add_option("--igtl-bind", options.igtlBind, "The address --igtl listens on (127.0.0.1)");
  app.add_option("--igtl-content", options.igtlContent, "The IMAGE Bone: fill (uint8) or density");
  app.add_flag("--no-ui", c.noUi, "Hide the panels (Tab toggles them)");
  app.add_flag("--mute", options.mute, "Start with the drill's sound muted (A toggles it)");
  app.add_flag("--no-tool", c.noTool,
               "Do not draw the tool (G toggles it), to see the hole it drilled");
}

// Turns the command line into options; throws InputError naming a bad value.
void settle(const CommandLine& c, viewer::ViewerOptions& options) {
  osteon::simulation::BoneSource& bone = options.load.bone;
  bone.input = c.input;
  bone.units = c.units.value_or("mm");
  bone.scale = c.scale;
  bone.voxelSizeMm = c.voxelSize;
  applyVolumeFlags(c.volume, bone.volume);
  bone.up = c.up;
  options.load.levels = c.levels;
  options.load.tool = osteon::simulation::parseToolKind(c.tool);
  options.load.path = c.path;
  options.load.device = c.device;
  if (!c.coupling.empty())
    options.load.coupling = osteon::simulation::parseCouplingMode(c.coupling);
  if (!c.forceModel.empty())
    options.load.forceModel = osteon::simulation::parseForceModelKind(c.forceModel);
  if (c.rpm) {
    osteon::simulation::validateRpm(*c.rpm);
    options.load.settings.rpm = *c.rpm;
  }
  options.load.settings.irrigation = c.irrigation;
  options.view = viewer::parseView(c.view);
  options.method = viewer::parseSurfaceChoice(c.method);
  viewer::parseCamera(c.camera, options.camera, options.cameraMode);
  options.load.scopeDevice = c.scopeDevice;
  options.load.exercise = c.exercise;
  if (c.focus != "bone" && c.focus != "tool") {
    throw osteon::InputError("--focus " + c.focus + ": expected bone or tool");
  }
  options.focusTool = c.focus == "tool";
  options.ui = !c.noUi;
  options.tool = !c.noTool;
  viewer::parseWindowSize(c.size, options.width, options.height);
  viewer::validateOptions(options);
}

// Everything about the input is settled, and the bone loaded, before a window opens.
int loadScene(const CommandLine& c, viewer::ViewerOptions& options,
              std::unique_ptr<viewer::Scene>& scene) {
  try {
    settle(c, options);
    scene = viewer::Scene::load(options.load);
    return kExitOk;
  } catch (const osteon::InputError& e) {
    return fail(kExitBadInput, osteon::simulation::commandLineMessage(e));
  } catch (const std::bad_alloc&) {
    return fail(kExitBadInput,
                "out of memory: the input needs more memory than this machine has (a larger "
                "--voxel-size needs less)");
  } catch (const std::exception& e) {
    return fail(kExitInternal, e.what());
  }
}

int runWindow(const viewer::ViewerOptions& options, std::unique_ptr<viewer::Scene> scene) {
  try {
    std::string json;
    {
      viewer::App window(options, std::move(scene));
      window.run();
      if (options.json) json = viewer::reportJson(window.report());
      if (const auto& s = window.igtlStats) {
        std::fprintf(stderr,
                     "osteon-viewer: OpenIGTLink: %llu client(s), %llu messages, %llu bytes sent, "
                     "%llu dropped\n",
                     static_cast<unsigned long long>(s->clients),
                     static_cast<unsigned long long>(s->messagesSent),
                     static_cast<unsigned long long>(s->bytesSent),
                     static_cast<unsigned long long>(s->dropped));
      }
    }  // the window closes here, before anything is printed
    if (options.json) std::cout << json << "\n";
    return kExitOk;
  } catch (const viewer::WindowError& e) {
    return fail(kExitBadInput, e.what());
  } catch (const osteon::InputError& e) {
    return fail(kExitBadInput, osteon::simulation::commandLineMessage(e));
  } catch (const std::bad_alloc&) {
    return fail(kExitBadInput, "out of memory");
  } catch (const std::exception& e) {
    return fail(kExitInternal, e.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "osteon-viewer: drill a bone with the mouse or a path, see the crack-free surface live"};
  app.set_version_flag("--version", std::string("osteon-viewer ") + OSTEON_VERSION);
  CommandLine c;
  viewer::ViewerOptions options;
  addBoneOptions(app, c);
  addToolOptions(app, c);
  addDisplayOptions(app, c, options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kExitOk;
  } catch (const CLI::CallForVersion&) {
    std::cout << "osteon-viewer " << OSTEON_VERSION << "\n";
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    return fail(kExitBadInput, std::string(e.what()) + " (see osteon-viewer --help)");
  }
  std::unique_ptr<viewer::Scene> scene;
  if (const int code = loadScene(c, options, scene); code != kExitOk) return code;
  return runWindow(options, std::move(scene));
}
