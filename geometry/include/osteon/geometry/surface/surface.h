// Surface extraction from the voxel grid (seed section 3.4, sharpened): marching cubes on the
// fill field at iso 1/2 with one shared vertex per crossed grid edge, so the surface is
// closed, 2-manifold and consistently oriented by construction; Laplacian smoothing that moves
// each vertex only along its own grid edge, so it cannot fold the surface; area-weighted
// normals. The seed's baseline, `naive`, gives every cube its own vertices and runs the same
// smoothing: that is what opens cracks.
#pragma once

#include <cstdint>
#include <vector>

#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/surface/buffer.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

enum class SurfaceMethod { CrackFree, Naive };
// "crackfree" or "naive", as the command line and reports name them.
inline const char* surfaceMethodName(SurfaceMethod m) {
  return m == SurfaceMethod::Naive ? "naive" : "crackfree";
}

struct SurfaceOptions {
  SurfaceMethod method = SurfaceMethod::CrackFree;
  int smoothIterations = 2;  // seed: two Laplacian passes
  double lambda = 0.5;       // Laplacian step
  bool taubin = false;       // alternate lambda and mu steps (no shrinkage)
  double mu = -0.53;         // Taubin's second step
  bool computeNormals = true;
};

// A surface ready for validation and rendering: positions, unit normals, outward CCW
// triangles grouped by the grid brick their cells belong to.
struct SurfaceMesh {
  Buffer<glm::dvec3> positionsMm;
  Buffer<glm::dvec3> normals;  // area-weighted, unit length (empty if not asked)
  Buffer<glm::u32vec3> triangles;
  // Triangles of the cells of one cell brick. Cells are numbered by their first voxel, from
  // -1 (the layer outside the grid that closes the surface) to dims - 1, and cell brick cb
  // holds cells 8 cb .. 8 cb + 7, so cb runs from -1 to brickDims - 1 on each axis.
  struct BrickRange {
    std::int64_t brick;    // key of the cell brick: (cb.x + 1) + (nb.x + 1) ((cb.y + 1) +
                           // (nb.y + 1) (cb.z + 1)), nb the grid's brickDims; stable across
                           // updates
    glm::ivec3 cellBrick;  // cb
    std::uint32_t first;   // triangles [first, first + count)
    std::uint32_t count;
  };
  std::vector<BrickRange> brickRanges;

  std::size_t vertexCount() const { return positionsMm.size(); }
  std::size_t triangleCount() const { return triangles.size(); }
  TriangleMesh toTriangleMesh() const {
    return TriangleMesh{{positionsMm.begin(), positionsMm.end()},
                        {triangles.begin(), triangles.end()}};
  }
};

// Where the time went, as the seed's Table 2.
struct SurfaceTimings {
  double extractMs = 0.0;  // marching cubes and triangle creation
  double smoothMs = 0.0;
  double normalsMs = 0.0;
  double otherMs = 0.0;  // adjacency, packing
  double totalMs = 0.0;
};

// Throws InputError for bad options: passes outside 0..100, lambda outside (0, 1], mu outside
// [-1, 0).
void validateSurfaceOptions(const SurfaceOptions& options);

// Throws InputError for bad options (see validateSurfaceOptions). Runs on TBB's threads. Each
// calling thread keeps the extraction's scratch between calls (under 1 KiB per cell brick that
// holds surface and 4 bytes per cell brick of the grid, sized by the largest extraction it has
// run), so repeated extractions do not fault in fresh pages; it is freed when the thread ends.
SurfaceMesh extractSurface(const VoxelGrid& grid, const SurfaceOptions& options = {},
                           SurfaceTimings* timings = nullptr);

class RefinedVoxels;

// Multi-resolution: where voxels are refined (levels -1, -2, seed 3.5), the surface is
// extracted on the refined lattice and joined to the level-0 surface without cracks. The
// refined lattice (spacing voxel / 2^depth) passes through the voxel centres; its samples are
// the mean of the eight sub-voxels around them inside the refined region (an unrefined voxel
// counting as sub-voxels of its own fill), and the trilinear interpolation of the voxel fills
// on the region's boundary faces. Cells with a refined corner are extracted on
// the refined lattice; level-0 cells sharing a face with them are transition cells whose loops
// follow the refined segments on that face (the face corners are unrefined, so the refined
// samples there are the bilinear interpolation of the same four fills and the crossings on
// the face's edges are the level-0 crossings). The whole surface stays closed, 2-manifold and
// consistently oriented. Always the crack-free method; brickRanges are left empty.
SurfaceMesh extractSurface(const VoxelGrid& grid, const RefinedVoxels& refined,
                           const SurfaceOptions& options = {}, SurfaceTimings* timings = nullptr);

}  // namespace osteon::geometry
