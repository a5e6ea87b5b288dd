// Packing osteon's state into OpenIGTLink messages (the reference library, protocol 2). Each
// function returns the whole message, header and body, ready to be written to any client.
// Coordinates go out in RAS, as Slicer expects: osteon's LPS with x and y negated.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/igtl/server.h"
#include "osteon/simulation/tool.h"

namespace osteon::igtl {

using Bytes = std::vector<std::uint8_t>;
using SharedBytes = std::shared_ptr<const Bytes>;

// The tool frame -> RAS of a pose in LPS, the tool frame flipped alike (F m F, F = diag(-1, -1,
// 1)): a rotation, under which the tool model is sent with toRas.
glm::dmat4 toolToRas(const simulation::ToolPose& pose);

SharedBytes packTransform(const std::string& name, const glm::dmat4& matrix);
// The voxels [lo, hi) of the grid as a sub-volume of the whole (uint8 fill 0..255, or int16
// density); the image's origin is the centre of the whole volume, its axes -x, -y, z.
SharedBytes packImage(const std::string& name, const geometry::VoxelGrid& grid,
                      ImageContent content, glm::ivec3 lo, glm::ivec3 hi);
SharedBytes packPolyData(const std::string& name, const std::vector<glm::dvec3>& pointsMm,
                         const std::vector<glm::u32vec3>& triangles, bool toRas);
SharedBytes packString(const std::string& name, const std::string& text);

// The tool's parts as closed cylinders in the tool frame (its model under DrillToRAS).
void toolModel(const simulation::Tool& tool, std::vector<glm::dvec3>& pointsMm,
               std::vector<glm::u32vec3>& triangles);

}  // namespace osteon::igtl
