// Mesh to voxels by Embree ray projection (seed 3.2): the mesh's bounding box padded by one
// voxel; for every grid column, a bundle of rays (4 x 4 by default) is cast through the mesh,
// every hit is collected, and the inside intervals of each ray (by parity) are overlapped
// exactly with the column's voxels, giving each voxel a fill fraction 0..255.
#pragma once

#include <cstdint>
#include <string>

#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/voxels/density.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

struct VoxelizeOptions {
  double voxelSizeMm = 1.0;
  int raysPerAxis = 4;    // rays per column = raysPerAxis^2, stratified over the column
  bool robust = false;    // all three axes, majority (median) vote, for damaged meshes
  int paddingVoxels = 1;  // empty voxels around the mesh's bounding box on every side
  DensityRule density;
  // Refuse a grid with no voxel at least half inside (InputError): drilling needs bone.
  bool requireInside = false;
  // For error messages only: the mesh's name (its file, or `default`), the factor it was
  // scaled by on loading (to suggest --units), whether the voxel size came from --voxel-size.
  std::string meshName;
  double loadScaleToMm = 1.0;
  bool voxelSizeGiven = true;
};

struct VoxelizeStats {
  std::uint64_t raysCast = 0;           // first casts (retries not included)
  std::uint64_t raysRetried = 0;        // rays re-cast, slightly moved, after an odd hit list
  std::uint64_t raysUnresolved = 0;     // rays still inconsistent after the retries
  std::uint64_t raysWinding = 0;        // rays through overlapping shells, classified by winding
  std::uint64_t disagreeingVoxels = 0;  // robust: voxels whose axis votes differ by > 1/2
  std::uint64_t abstainedColumns = 0;   // robust: columns with no consistent ray on an axis
  bool orientedMesh = false;            // facing of hits was used to check rays
  DensityStats density;
  double raysMs = 0.0;     // ray casting and fill, all axes
  double combineMs = 0.0;  // robust vote
  double densityMs = 0.0;
  double bvhMs = 0.0;
  double totalMs = 0.0;
};

// The grid that voxelize() would make for this mesh and voxel size: dims and origin, the
// mesh's bounding box in it with paddingVoxels to paddingVoxels + 1 on each side, voxel faces
// on multiples of the voxel size (grids of sizes VS and VS / 2^k nest). Throws InputError when
// the voxel size is not positive and finite or the grid would exceed VoxelGrid::kMaxVoxels.
VoxelGrid makeGridFor(const TriangleMesh& mesh, double voxelSizeMm, int paddingVoxels = 1);

// Throws InputError for bad options (voxel size not positive and finite, or larger than the
// mesh's largest extent; rays per axis outside 1..16; density rule), for a grid past
// VoxelGrid::kMaxVoxels, and with requireInside for a grid with no voxel inside; the messages
// name the mesh, its extent and the voxel size, and suggest --units when the extent looks
// like another unit read as millimetres.
VoxelGrid voxelize(const TriangleMesh& mesh, const VoxelizeOptions& options,
                   VoxelizeStats* stats = nullptr);

}  // namespace osteon::geometry
