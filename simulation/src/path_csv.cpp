// A drill path written as the CSV loadPathCsv reads (path.h).
#include <cstdio>
#include <string>

#include "osteon/simulation/path.h"

namespace osteon::simulation {

std::string drillPathCsv(const DrillPath& path) {
  std::string out = "t,x,y,z,drill_on,qw,qx,qy,qz\n";
  char line[512];
  for (const Waypoint& w : path.points()) {
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g,%.17g,%.17g\n", w.tS,
                  w.tipMm.x, w.tipMm.y, w.tipMm.z, w.drillOn ? 1 : 0, w.orientation.w,
                  w.orientation.x, w.orientation.y, w.orientation.z);
    out += line;
  }
  return out;
}

}  // namespace osteon::simulation
