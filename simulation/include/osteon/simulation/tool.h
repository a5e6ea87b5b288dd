// Surgical tools as data (seed 3.5): every tool is a list of parts, each a two-layer shape
// around a core segment in the tool's frame. The inner layer removes material (when the part
// cuts); the shell between the inner and the outer layer is the cushion whose bone gives the
// force. A sphere is a part whose segment is a point.
//
// Tool frame: the tip's centre at the origin, the handle along +z. A pose places that frame in
// the world (tip position, orientation).
#pragma once

#include <array>
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace osteon::simulation {

enum class ToolKind { Drill, Burr, Shaver };

// Parses "drill", "burr", "shaver"; throws InputError naming the value otherwise.
ToolKind parseToolKind(const std::string& text);
const char* toolKindName(ToolKind kind);

struct ToolPart {
  glm::dvec3 aMm{0.0};  // core segment, tool frame
  glm::dvec3 bMm{0.0};
  double innerRadiusMm = 0.0;  // removes material inside (when `cuts`)
  double outerRadiusMm = 0.0;  // the shell (inner, outer] gives the force
  bool cuts = false;
  bool cutsOnSideOnly = false;  // cuts only where the projection falls on the segment

  double lengthMm() const;
  // Shell volume: pi (ro^2 - ri^2) L + 4/3 pi (ro^3 - ri^3).
  double shellVolumeMm3() const;
};

inline constexpr int kMaxToolParts = 2;

struct Tool {
  ToolKind kind = ToolKind::Drill;
  std::array<ToolPart, kMaxToolParts> parts{};
  int partCount = 0;
  double maxForceN = 3.3;         // N_max, what the haptic device can exert (seed 3.5)
  bool literalSeedCount = false;  // c as printed in the seed (see contact.h)
};

struct ToolOptions {
  double tipDiameterMm = 2.92;   // drill tip and burr sphere; shaver cylinder (seed 4)
  double cushionVoxels = 2.0;    // outer = inner + this many finest voxel sizes
  double outerRadiusMm = -1.0;   // > 0: the outer radius of the cutting part, overriding
  double shaftDiameterMm = 2.0;  // drill: the shaft behind the tip, collides, never cuts
  double shaftLengthMm = 30.0;
  double shaverWindowMm = 4.0;  // shaver: length of the cylinder that cuts on its side
  double maxForceN = 3.3;
  bool literalSeedCount = false;  // c as printed in the seed's eq. (2) (see contact.h)
};

// Throws InputError naming the option for non-positive or inconsistent sizes.
void validateToolOptions(const ToolOptions& options);

// finestVoxelMm: the finest voxel size forces are computed at (base / 2^levels).
Tool makeTool(ToolKind kind, const ToolOptions& options, double finestVoxelMm);

// Pose of the tool frame in the world.
struct ToolPose {
  glm::dvec3 tipMm{0.0};
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};  // tool frame -> world

  glm::dvec3 toWorld(const glm::dvec3& toolMm) const { return tipMm + orientation * toolMm; }
  // The unit direction the tool points to (from the handle to the tip).
  glm::dvec3 forward() const { return orientation * glm::dvec3(0.0, 0.0, -1.0); }
  // A pose at tipMm pointing along forward (unit or not; zero keeps the default).
  static ToolPose pointing(const glm::dvec3& tipMm, const glm::dvec3& forward);
};

}  // namespace osteon::simulation
