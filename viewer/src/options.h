// What osteon-viewer is asked to do, free of CLI11 (main.cpp parses into it) and of GL, so the
// checks that run before any window opens compile and test apart.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "camera.h"
#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/coupling.h"
#include "osteon/simulation/tool.h"

namespace osteon::viewer {

// What the bone is coloured by (keys F1..F6, the Views panel, --view).
enum class View { Shaded, Cracks, Levels, Density, Hierarchy, Wireframe, Heat };
// Which surface the crack view (and every view) draws: the live incremental one, or the seed's
// naive marching cubes extracted whole again whenever bricks changed (a comparison view).
enum class SurfaceChoice { CrackFree, Naive };

const char* viewName(View view);
// "shaded", "cracks", "levels", "density", "hierarchy", "wireframe", "heat"; throws InputError
// naming the value otherwise.
View parseView(const std::string& text);
const char* surfaceChoiceName(SurfaceChoice method);
// "crackfree" or "naive"; throws InputError naming the value otherwise.
SurfaceChoice parseSurfaceChoice(const std::string& text);
// "anterior", "posterior", "right", "left", "superior", "inferior"; throws InputError naming
// the value otherwise.
AxisView parseAxisView(const std::string& text);

// The main view's camera: the orbit camera (axis views, drags), the arthroscope at its portal,
// or a camera that follows the tool's tip.
enum class CameraMode { Orbit, Scope, Follow };
const char* cameraModeName(CameraMode mode);
// --camera: an axis view (the orbit camera), `scope` or `follow`; throws InputError naming the
// value otherwise.
void parseCamera(const std::string& text, AxisView& axis, CameraMode& mode);

// What a bone is opened from (the command line, the File panel, a dropped file).
inline constexpr double kDefaultVoxelSizeMm = 1.2;

struct LoadRequest {
  // A mesh file, `default`, or a volume, with its units, voxel size and meaning; a mesh without
  // a voxel size is voxelized at kDefaultVoxelSizeMm.
  simulation::BoneSource bone = defaultBone();
  int levels = 2;  // 0 static, 1 or 2 refined near the tool
  simulation::ToolKind tool = simulation::ToolKind::Drill;
  std::string path;    // "" (the mouse), portal-5, portal-7 or a PATH.csv
  std::string device;  // "" (the mouse or the path), or a device name (docs/devices.md)
  // An exercise (a built-in name or a JSON file): its bone, tool and levels replace the ones
  // above, its plan is drawn and the trial scored. With it, path "plan" plays its ideal path.
  std::string exercise;
  // The arthroscope's device, a second slot ("": the mouse moves the scope); its pose is the
  // scope's tip and shaft, its knob the lens rotation.
  std::string scopeDevice;
  // --coupling; unset: direct for portal paths, proxy for the mouse, devices and CSV paths.
  std::optional<simulation::CouplingMode> coupling;
  // --force-model; unset: calibrated when a hand drives (the mouse, a device), the seed's for
  // paths (their runs are the paper's). --rpm and --irrigation: the drill's start settings.
  std::optional<simulation::ForceModelKind> forceModel;
  simulation::DrillSettings settings;

  static simulation::BoneSource defaultBone() {
    simulation::BoneSource bone;
    bone.defaultVoxelSizeMm = kDefaultVoxelSizeMm;
    return bone;
  }
};

struct ViewerOptions {
  LoadRequest load;
  View view = View::Shaded;
  SurfaceChoice method = SurfaceChoice::CrackFree;
  AxisView camera = AxisView::Anterior;  // the start view, framed on the bone
  CameraMode cameraMode = CameraMode::Orbit;
  bool pictureInPicture = false;  // a second view in the corner (P toggles)
  double zoom = 1.0;              // > 1 magnifies the start view
  bool focusTool = false;         // centre the start view on the tool's first pose
  int width = 1280, height = 800;
  int frames = 0;          // > 0: render this many frames and exit
  std::string screenshot;  // PNG of the last frame
  std::string record;      // the tool's path, recorded from the start to exit
  bool json = false;       // one JSON object on stdout at exit
  bool ui = true;          // the ImGui panels (Tab toggles)
  bool mute = false;       // start with the drill's sound muted (A toggles it; sound.h)
  bool tool = true;        // draw the tool (G toggles)
  // --igtl PORT: the session served over OpenIGTLink (osteon/igtl/server.h, docs/slicer.md).
  std::optional<int> igtlPort;
  std::string igtlBind = "127.0.0.1";
  std::string igtlContent = "fill";
};

// An exercise: a built-in name (anchor-5, ...) or a .json file.
bool isExercise(const std::string& input);

// A mesh file (.stl .obj .ply .off, any case): its coordinates carry no unit, so the window
// asks for one each time such a file is opened (volumes and `default` know theirs).
bool fileNeedsUnits(const std::string& input);
// What opening `input` from the window (the File panel, a dropped file) loads: the session's
// levels, tool, coupling and devices, the mouse rather than a path, and of the bone only what
// was chosen for this file: `scaleToMm` (its unit, asked for a mesh file) and `voxelMm`.
// Nothing of the previous file's unit, scale, label or iso carries over.
LoadRequest requestForFile(const LoadRequest& current, const std::string& input,
                           std::optional<double> scaleToMm, double voxelMm);

// Parses "WxH" (e.g. 1280x800), each 64..8192; throws InputError naming the value otherwise.
void parseWindowSize(const std::string& text, int& width, int& height);

// Everything that can be refused without loading: the bone's options (BoneSource::check),
// levels, frame count, zoom, outputs that would overwrite an input. Throws InputError
// "<value>: <reason>" (the bone's options named by their flags).
void validateOptions(const ViewerOptions& options);

}  // namespace osteon::viewer
