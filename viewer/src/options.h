// What osteon-viewer is asked to do, free of CLI11 (main.cpp parses into it) and of GL, so the
// checks that run before any window opens compile and test apart.
#pragma once

#include "camera.h"

#include "osteon/simulation/coupling.h"
#include "osteon/simulation/tool.h"

#include <cstdint>
#include <optional>
#include <string>

namespace osteon::viewer {

// What the bone is coloured by (keys F1..F6, the Views panel, --view).
enum class View { Shaded, Cracks, Levels, Density, Hierarchy, Wireframe };
// Which surface the crack view (and every view) draws: the live incremental one, or the seed's
// naive marching cubes extracted whole again whenever bricks changed (a comparison view).
enum class SurfaceChoice { CrackFree, Naive };

const char* viewName(View view);
// "shaded", "cracks", "levels", "density", "hierarchy", "wireframe"; throws InputError
// naming the value otherwise.
View parseView(const std::string& text);
const char* surfaceChoiceName(SurfaceChoice method);
// "crackfree" or "naive"; throws InputError naming the value otherwise.
SurfaceChoice parseSurfaceChoice(const std::string& text);
// "anterior", "posterior", "right", "left", "superior", "inferior"; throws InputError naming
// the value otherwise.
AxisView parseAxisView(const std::string& text);

// What a bone is opened from (the command line, the File panel, a dropped file).
struct LoadRequest {
  std::string input = "default";        // a mesh file, `default`, or a volume (.nrrd .nhdr .nii .nii.gz)
  double scaleToMm = 1.0;               // mesh coordinates to millimetres
  std::optional<double> voxelSizeMm;    // a mesh without it is voxelized at kDefaultVoxelSizeMm
  int levels = 2;                       // 0 static, 1 or 2 refined near the tool
  simulation::ToolKind tool = simulation::ToolKind::Drill;
  std::string path;                     // "" (the mouse), portal-5, portal-7 or a PATH.csv
  std::string device;                   // "" (the mouse or the path), or a device name (docs/devices.md)
  std::optional<std::uint64_t> label;   // label maps: the bone label (default: all but the background)
  std::optional<double> isoHu;          // CTs: the bone threshold (default 300 HU)
  bool allowOutsideData = false;        // NRRD: a `data file:` may lie outside the header's folder
  // --coupling; unset: direct for portal paths, proxy for the mouse, devices and CSV paths.
  std::optional<simulation::CouplingMode> coupling;
};

inline constexpr double kDefaultVoxelSizeMm = 1.2;

struct ViewerOptions {
  LoadRequest load;
  View view = View::Shaded;
  SurfaceChoice method = SurfaceChoice::CrackFree;
  AxisView camera = AxisView::Anterior;  // the start view, framed on the bone
  double zoom = 1.0;                      // > 1 magnifies the start view
  bool focusTool = false;                 // centre the start view on the tool's first pose
  int width = 1280, height = 800;
  int frames = 0;            // > 0: render this many frames and exit
  std::string screenshot;    // PNG of the last frame
  std::string record;        // the tool's path, recorded from the start to exit
  bool json = false;         // one JSON object on stdout at exit
  bool ui = true;            // the ImGui panels (Tab toggles)
  bool tool = true;          // draw the tool (G toggles)
};

// Parses "WxH" (e.g. 1280x800), each 64..8192; throws InputError naming the value otherwise.
void parseWindowSize(const std::string& text, int& width, int& height);

// Millimetres per file unit from --units or --scale; throws InputError for bad values.
double scaleToMmFrom(const std::optional<std::string>& units, const std::optional<double>& scale);

// True for a volume (an osteon grid, a label map or a CT: .nrrd .nhdr .nii .nii.gz), which
// has its own voxel size.
bool isGridPath(const std::string& path);
// True when a --path argument names a CSV file rather than a portal.
bool isCsvPath(const std::string& path);

// Everything that can be refused without loading: voxel size, levels, frame count, zoom, outputs
// that would overwrite an input. Throws InputError "<value>: <reason>".
void validateOptions(const ViewerOptions& options);

}  // namespace osteon::viewer
