// Exact splitting of a voxel's fill over its 64 level -2 sub-voxels (refinement, seed 3.5).
#pragma once

#include <array>
#include <cstdint>

#include "osteon/geometry/hierarchy/fine_fill.h"

namespace osteon::geometry::detail {

inline constexpr Fill kSubFull = kFillFull / kSubVoxels;  // a full level -2 sub-voxel: 255 units

// Splits `total` fill units over 64 sub-voxels in proportion to `weights` (evenly without),
// exactly, none above a full sub-voxel.
void distributeExactly(const std::array<std::uint8_t, kSubVoxels>* weights, Fill total,
                       std::array<Fill, kSubVoxels>& out);

// Sampled sub-voxel fills adjusted to sum exactly to `total`, the difference spread over the
// sub-voxels the surface passes through.
void fitToTotal(const std::array<std::uint8_t, kSubVoxels>& sampled, Fill total,
                std::array<Fill, kSubVoxels>& out);

}  // namespace osteon::geometry::detail
