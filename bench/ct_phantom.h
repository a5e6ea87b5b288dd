// A clinical-size bone CT phantom (512 x 512 x 350 int16 HU, raw NRRD): two long bones along S,
// each a cortical shell (1000-1500 HU, varying along the shaft) around cancellous bone
// (400-550 HU) ending in a round head, in -1000 HU air, with +-20 HU noise per stored voxel.
// The bones are defined in LPS mm and sampled at each stored voxel's centre, so the surface the
// iso ramp makes lies where the scanner would have put it whatever the spacing or tilt.
#pragma once

#include <string>

namespace osteon::bench {

// KIND: "iso" (0.7 mm cubes), "aniso" (0.7 x 0.7 x 1 mm, the common clinical case), "thick"
// (0.98 x 0.98 x 2 mm), "oblique" (0.7 x 0.7 x 1 mm rotated 15 degrees, a gantry tilt) or
// "labels" (aniso's bone as a uint8 label map: 1 at or above 300 HU).
// Returns false for an unknown kind; throws std::runtime_error when the file cannot be written.
bool writeCtPhantom(const std::string& kind, const std::string& path);

}  // namespace osteon::bench
