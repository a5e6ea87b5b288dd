#include "osteon/simulation/tool.h"

#include <cmath>
#include <sstream>

#include <glm/geometric.hpp>

#include "osteon/core/checks.h"
#include "osteon/core/error.h"
#include "osteon/core/option_error.h"

namespace osteon::simulation {

ToolKind parseToolKind(const std::string& text) {
  if (text == "drill") return ToolKind::Drill;
  if (text == "burr") return ToolKind::Burr;
  if (text == "shaver") return ToolKind::Shaver;
  throw OptionError("tool", text, "unknown tool (use drill, burr or shaver)");
}

const char* toolKindName(ToolKind kind) {
  switch (kind) {
    case ToolKind::Drill:
      return "drill";
    case ToolKind::Burr:
      return "burr";
    case ToolKind::Shaver:
      return "shaver";
  }
  return "?";
}

double ToolPart::lengthMm() const {
  return glm::length(bMm - aMm);
}

double ToolPart::shellVolumeMm3() const {
  const double ro = outerRadiusMm, ri = innerRadiusMm;
  return M_PI * (ro * ro - ri * ri) * lengthMm() + 4.0 / 3.0 * M_PI * (ro * ro * ro - ri * ri * ri);
}

void validateToolOptions(const ToolOptions& o) {
  requirePositive(o.tipDiameterMm, "tool tip diameter (mm)");
  requirePositive(o.cushionVoxels, "tool cushion (finest voxels)");
  requirePositive(o.shaftDiameterMm, "drill shaft diameter (mm)");
  requirePositive(o.shaftLengthMm, "drill shaft length (mm)");
  requirePositive(o.shaverWindowMm, "shaver window length (mm)");
  requirePositive(o.maxForceN, "maximum force (N)");
  if (o.outerRadiusMm > 0.0 && o.outerRadiusMm <= 0.5 * o.tipDiameterMm) {
    std::ostringstream s;
    s << "tool outer radius " << o.outerRadiusMm << " mm: must exceed the inner radius "
      << 0.5 * o.tipDiameterMm << " mm";
    throw InputError(s.str());
  }
  if (o.shaftDiameterMm >= o.tipDiameterMm) {
    std::ostringstream s;
    s << "drill shaft diameter " << o.shaftDiameterMm << " mm: must be below the tip's "
      << o.tipDiameterMm << " mm (the shaft follows the tip into its hole)";
    throw InputError(s.str());
  }
}

Tool makeTool(ToolKind kind, const ToolOptions& o, double finestVoxelMm) {
  validateToolOptions(o);
  if (!(finestVoxelMm > 0.0)) throw InputError("finest voxel size: must be positive");
  Tool tool;
  tool.kind = kind;
  tool.maxForceN = o.maxForceN;
  tool.literalSeedCount = o.literalSeedCount;
  const double ri = 0.5 * o.tipDiameterMm;
  const double ro = o.outerRadiusMm > 0.0 ? o.outerRadiusMm : ri + o.cushionVoxels * finestVoxelMm;
  ToolPart cutter;
  cutter.innerRadiusMm = ri;
  cutter.outerRadiusMm = ro;
  cutter.cuts = true;
  if (kind == ToolKind::Shaver) {
    // The window runs back from the tip along the axis; the rounded ends push but do not cut.
    cutter.bMm = glm::dvec3(0.0, 0.0, o.shaverWindowMm);
    cutter.cutsOnSideOnly = true;
  }
  tool.parts[0] = cutter;
  tool.partCount = 1;
  if (kind == ToolKind::Drill) {
    // The shaft starts behind the tip sphere. Its cushion reaches out to the tip's radius and
    // no further: in a straight hole the tip cut, the shaft touches nothing; levered against
    // the hole's wall it pushes back.
    ToolPart shaft;
    shaft.aMm = glm::dvec3(0.0, 0.0, ri);
    shaft.bMm = glm::dvec3(0.0, 0.0, ri + o.shaftLengthMm);
    shaft.innerRadiusMm = 0.5 * o.shaftDiameterMm;
    shaft.outerRadiusMm = std::min(shaft.innerRadiusMm + o.cushionVoxels * finestVoxelMm, ri);
    tool.parts[1] = shaft;
    tool.partCount = 2;
  }
  return tool;
}

ToolPose ToolPose::pointing(const glm::dvec3& tipMm, const glm::dvec3& forward) {
  ToolPose pose;
  pose.tipMm = tipMm;
  const double len = glm::length(forward);
  if (!(len > 0.0)) return pose;
  // The tool's -z goes to `forward`: rotate -z onto it by the shortest arc.
  const glm::dvec3 from(0.0, 0.0, -1.0), to = forward / len;
  const double c = glm::dot(from, to);
  if (c < -1.0 + 1e-12) {
    pose.orientation = glm::dquat(0.0, 1.0, 0.0, 0.0);  // half turn about x
  } else {
    const glm::dvec3 axis = glm::cross(from, to);
    pose.orientation = glm::normalize(glm::dquat(1.0 + c, axis.x, axis.y, axis.z));
  }
  return pose;
}

}  // namespace osteon::simulation
