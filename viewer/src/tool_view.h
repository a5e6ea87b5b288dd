// What the viewer shows of the tool under proxy coupling, without GL: the proxy (the tool the
// bone stops) is always drawn; a ghost of the commanded pose (the hand's) joins it when the two
// differ by more than a hair, so a trainee sees how far past the surface they are pushing. The
// same place measures how deep either pose reaches into bone, for --json and the tests.
#pragma once

#include <cstdint>

#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/simulation/tool.h"

namespace osteon::viewer {

// Below this the ghost would sit inside the proxy's own drawing: 0.05 mm is a sixth of the
// finest voxel at 1.2 mm / 2 levels, and under a pixel at every zoom the viewer frames.
inline constexpr double kGhostThresholdMm = 0.05;

// The largest distance any point of the tool's part segments moves from pose a to pose b.
// For a rigid motion a point's displacement is affine along a segment, so its largest length
// is at an end: a turn about the tip shows at the shaft's far end, not at the tip.
double toolOffsetMm(const simulation::Tool& tool, const simulation::ToolPose& a,
                    const simulation::ToolPose& b);

// Whether the commanded pose is drawn as a ghost beside the proxy.
bool showGhost(const simulation::Tool& tool, const simulation::ToolPose& proxy,
               const simulation::ToolPose& commanded, double thresholdMm = kGhostThresholdMm);

// How deep the tool at `pose` sits in bone: how far a part would have to back out along the
// tool's axis (every part of osteon's tools lies on it) until no voxel at least half full has
// its centre inside that part's inner layer, the largest over the parts; 0 when no part holds
// such a voxel. Each part on its own, and only the bone inside it now, so the value is at most
// a part's length plus its diameter: the drill's 30 mm shaft measures a push of 10 mm into
// bone (about 10 mm less the shaft's offset behind the tip); the burr's lone sphere says 2.9 mm
// for any push past that. A proxy in contact keeps this within about its cushion (level-0
// centres stand for their sub-voxels, so inside a drilled hole half-cut voxels add to it).
double boneDepthMm(const geometry::VoxelGrid& grid, const simulation::Tool& tool,
                   const simulation::ToolPose& pose);

// Frame by frame: what was drawn and how deep each pose reached (the --json fields).
struct ToolViewTally {
  std::uint64_t ghostFrames = 0;
  bool ghostLast = false;
  double gapLastMm = 0.0;
  double maxProxyDepthMm = 0.0;
  double maxCommandedDepthMm = 0.0;

  // One frame; `grid` null skips the depths (it walks the voxels around both poses).
  void add(const simulation::Tool& tool, const simulation::ToolPose& proxy,
           const simulation::ToolPose& commanded, double gapMm, const geometry::VoxelGrid* grid);
};

}  // namespace osteon::viewer
