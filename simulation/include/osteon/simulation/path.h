// Drill paths (seed 4): the 5 o'clock (anteroinferior) and 7 o'clock (posteroinferior)
// portals on the humeral head, and arbitrary paths from CSV.
//
// The head comes from a sphere fitted to the mesh, so any humerus works: the bone's long axis
// by principal components, the sphere fitted robustly at each end of it, the head being the
// end that a sphere fits best (HeadEnd). Superior points from the shaft to the head; medial
// from the shaft axis to the head centre; anterior = medial x superior for a right humerus (a
// left one mirrors it).
//
// Portal paths: the clock face is drawn on the articular surface around the head axis (the
// direction from the head centre to the middle of the points on the sphere), 12 o'clock
// towards superior and 3 o'clock towards anterior (right shoulder), each hour 45 degrees off
// the axis. The entry point is on the bone's surface in that direction from the head centre;
// the drill enters at 45 degrees to the surface normal, tilted towards the articular pole so
// the hole stays in the head, starts with its cushion clear of the surface and moves at
// constant speed for 7 s with the drill on, to a depth of 15 mm past the entry point: the
// depth of a suture-anchor hole, which is what the seed's drilling prepares.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "osteon/geometry/io/mesh.h"
#include "osteon/simulation/tool.h"

namespace osteon::simulation {

struct HumeralHead {
  glm::dvec3 centreMm{0.0};
  double radiusMm = 0.0;
  double rmsResidualMm = 0.0;  // of the points the fit kept
  int pointsUsed = 0;
  glm::dvec3 axis{0.0};  // from the centre through the middle of the articular surface
  glm::dvec3 superior{0.0, 0.0, 1.0};
  glm::dvec3 medial{1.0, 0.0, 0.0};
  glm::dvec3 anterior{0.0, -1.0, 0.0};
  // What checkHumeralHead() judges: the area of the surface on the sphere (the fit's points),
  // the bone's length along its long axis, and how far the sphere's top lies from that end.
  double capAreaMm2 = 0.0;
  double boneLengthMm = 0.0;
  double endGapMm = 0.0;
};

// A humeral head is 18-30 mm in radius (adult humeri, 19-28 mm), at one end of the bone: its
// top within a radius of the bone's end, its sphere covering a cap of at least this share of
// the sphere's area.
inline constexpr double kMinHeadRadiusMm = 18.0;
inline constexpr double kMaxHeadRadiusMm = 30.0;
inline constexpr double kMinHeadCapShare = 0.03;

// Which end of the bone is the head, of the ends a sphere fits.
enum class HeadEnd {
  // The end that a sphere fits best for its size (rms / radius): meshes.
  TightestSphere,
  // The end whose sphere holds the most surface area: surfaces extracted from a voxel grid,
  // where any rounded end (a cut shaft's cap, the capitulum) has thousands of points and fits
  // its small sphere as tightly as the head fits its large one.
  LargestCap,
};

// Throws InputError when the mesh has too few points or no end fits a sphere.
// up: the unit direction from the shaft to the head (BoneSource::up); then the bone's long
// axis is taken as up and the head sought at that end only.
HumeralHead fitHumeralHead(const geometry::TriangleMesh& mesh, bool rightSide = true,
                           HeadEnd headEnd = HeadEnd::TightestSphere,
                           const std::optional<glm::dvec3>& up = std::nullopt);
// Throws InputError, one line naming `name` (the bone's file) and suggesting --up or an
// explicit entry point, unless the fit is a humeral head by the limits above.
void checkHumeralHead(const HumeralHead& head, const std::string& name);
// "x", "-y", ...: the unit axis; throws OptionError naming the field "up" otherwise.
glm::dvec3 parseUpAxis(const std::string& text);

// The longest drill path accepted from user data (an hour): the run's length, and so its
// time and its logs, follow from the path's end time.
inline constexpr double kMaxPathDurationS = 3600.0;
// Coordinates beyond this are no place on a bone in any unit (as for meshes).
inline constexpr double kMaxPathCoordinateMm = 1e9;

enum class Portal { FiveOClock, SevenOClock };

struct Waypoint {
  double tS = 0.0;
  glm::dvec3 tipMm{0.0};
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
  bool drillOn = false;
};

// Piecewise-linear in time (orientations by normalized lerp).
class DrillPath {
 public:
  DrillPath() = default;
  explicit DrillPath(std::vector<Waypoint> points);  // times strictly increasing
  double durationS() const { return points_.empty() ? 0.0 : points_.back().tS; }
  const std::vector<Waypoint>& points() const { return points_; }
  // The pose and drill state at time t (clamped to the path's ends). No allocation.
  void sample(double tS, ToolPose& pose, bool& drillOn) const;

 private:
  std::vector<Waypoint> points_;
  mutable std::size_t cursor_ = 0;  // the last segment used: samples mostly move forward
};

struct PortalPathOptions {
  double durationS = 7.0;
  double depthMm = 15.0;        // past the entry point, along the path
  double entryAngleDeg = 45.0;  // to the surface normal
  double clearanceMm = 1.0;     // between the cushion and the surface at the start
  double clockConeDeg = 45.0;   // the clock face's angle from the head axis
  // The tool turned about its tip by this much, in the plane of travel and the surface
  // normal, its tip towards the inward normal (the handle rising past the perpendicular at
  // 45): the tip follows the same path, the shaft levers against the hole's rim and wall.
  double tiltDeg = 0.0;
};

struct PortalPlan {
  DrillPath path;
  glm::dvec3 entryMm{0.0};         // on the bone surface
  glm::dvec3 normal{0.0};          // outward at the entry
  glm::dvec3 clockDirection{0.0};  // from the head centre
  glm::dvec3 direction{0.0};       // of travel
  double speedMmPerS = 0.0;
};

// Portal names: "portal-5", "portal-7".
Portal parsePortal(const std::string& text);
// The entry point is where the ray from the head centre towards the clock position leaves
// the bone for the last time (the mesh's outer surface there); the 45 degrees are to that
// triangle's normal. Throws InputError when the ray never leaves the bone.
PortalPlan makePortalPath(Portal portal, const HumeralHead& head,
                          const geometry::TriangleMesh& mesh, double toolOuterRadiusMm,
                          const PortalPathOptions& options = {});

// CSV with a header row: t, x, y, z, drill_on [, qw, qx, qy, qz] (seconds, millimetres, 0/1,
// the tool's orientation, any non-zero scale; without it the tool points along the direction
// of travel), optionally after a UTF-8 byte order mark. Times from 0 to kMaxPathDurationS.
// Throws InputError naming the file and line for anything else.
DrillPath loadPathCsv(const std::string& path);
// The path as that CSV, with its orientations (t,x,y,z,drill_on,qw,qx,qy,qz; 17 digits, so it
// reads back to the same path).
std::string drillPathCsv(const DrillPath& path);
// True when a path argument names a CSV file (its extension, any case) rather than a portal.
bool isPathCsv(const std::string& path);

}  // namespace osteon::simulation
