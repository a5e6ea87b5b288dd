// The marching-cubes case table, generated (not copied) from one rule per cube face.
//
// Corner c of a cell sits at offset (c & 1, c >> 1 & 1, c >> 2 & 1). Edge e = 4 * axis + k
// runs along `axis` from corner (bu << u) | (bv << v), k = bu + 2 bv, u = axis + 1, v = axis + 2
// (mod 3). A corner is inside when its fill is at or above the iso value.
//
// On each face the iso line crosses 0, 2 or 4 edges. Two crossings give one segment. Four (an
// ambiguous face: inside corners on one diagonal) give two segments, each cutting off one
// outside corner, so inside corners always connect across the face. The rule reads only the
// face's four corners, so both cells sharing a face draw the same segments: no configuration
// can open a hole. Segments are oriented so the inside lies on one fixed side; they join into
// closed loops on the cube's surface, and each loop becomes a fan of outward triangles.
#pragma once

#include <array>
#include <cstdint>

namespace osteon::geometry::detail {

struct McCase {
  std::uint8_t loopCount = 0;
  std::array<std::uint8_t, 5> loopBegin{};  // loop i spans edges[loopBegin[i] .. loopBegin[i+1])
  std::array<std::uint8_t, 13> edges{};     // cube edges, loop after loop, in outward order
};

// Corner index at each end of a cube edge.
std::array<std::uint8_t, 2> edgeCorners(int edge);
// The 256 cases (config bit c set: corner c inside).
const std::array<McCase, 256>& mcTable();

}  // namespace osteon::geometry::detail
