// osteon::simulation: what will live here (seed sections 3.5 and 4).
//   - tools as data: drill, burr, shaver, each a two-layer shape (inner removes, outer cushions)
//   - collision through the proximity hierarchy at the finest refined level
//   - the force model of eq. (1)-(2), clamped to N_max, never NaN
//   - material removal: integer density decrement, voxel removal, dirty bricks
//   - the three-thread runtime (haptic 1 kHz, collision 1 kHz, visual) and a deterministic mode
//   - drill paths (the seed's 5 and 7 o'clock portals, CSV paths) and force logs
// Depends on osteon::geometry only.
#pragma once

namespace osteon::simulation {

// Version of the simulation module's interface; bumped when the first real API lands.
inline constexpr int kInterfaceVersion = 0;

}  // namespace osteon::simulation
