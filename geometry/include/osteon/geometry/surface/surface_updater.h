// The crack-free surface kept up to date as bone is drilled: after a change, only the cell
// bricks that read changed voxels are extracted again, and only the vertices within the
// smoothing's reach of the change are smoothed again. The result equals a full extraction of
// the new grid (same triangles, vertex positions to rounding).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

// What changed in an updater's surface since the last SurfaceUpdater::takeChanges(), in its
// stable numbering: a vertex slot keeps its index while the vertex lives, and a cell brick's
// triangles (in slot indices) are replaced whole when the brick changes. A front end keeps a
// vertex buffer indexed by slot and one triangle range per brick, and uploads only these.
struct SurfaceDelta {
  std::size_t slotCount = 0;            // slots in use or free: vertex buffer size
  std::vector<std::uint32_t> slots;     // slots whose position or normal changed, or that died
  std::vector<glm::dvec3> positionsMm;  // per listed slot (NaN for a dead slot)
  std::vector<glm::dvec3> normals;
  struct Brick {
    std::int64_t key;                     // SurfaceMesh::BrickRange::brick
    std::vector<glm::u32vec3> triangles;  // the brick's triangles now (empty: none left)
  };
  std::vector<Brick> bricks;
  bool everything = false;  // the first read: every slot and brick is listed
};

class SurfaceUpdater {
 public:
  struct UpdateStats {
    std::size_t cellBricks = 0;        // cell bricks extracted again
    std::size_t verticesTouched = 0;   // created, moved by their edge, or with new triangles
    std::size_t verticesSmoothed = 0;  // positions recomputed
    double ms = 0.0;                   // all of the update
    double extractMs = 0.0;            // edges and triangles of the changed cells
    double smoothMs = 0.0;             // smoothing and normals
  };

  // Extracts the whole surface of `grid` (always the crack-free method; options.method is
  // ignored). The grid must outlive the updater. Throws InputError for bad options.
  SurfaceUpdater(const VoxelGrid& grid, const SurfaceOptions& options = {});
  // The same, extracting `asItWas` (the grid as it was, e.g. the bone before drilling: the same
  // shape, origin and voxel size, else std::logic_error) so that `grid` may change while this
  // runs on another thread; update() then with the bricks changed since reads `grid`.
  SurfaceUpdater(const VoxelGrid& grid, const SurfaceOptions& options, const VoxelGrid& asItWas);
  ~SurfaceUpdater();
  SurfaceUpdater(const SurfaceUpdater&) = delete;
  SurfaceUpdater& operator=(const SurfaceUpdater&) = delete;

  // Brings the surface up to date after the voxels of these grid bricks changed (for example
  // grid.dirtyBricks(), then grid.clearDirty()).
  UpdateStats update(const std::vector<std::size_t>& changedGridBricks);

  // The current surface as compact arrays, triangles grouped by cell brick.
  SurfaceMesh mesh() const;
  // The changes since the last call (everything on the first), and forget them.
  SurfaceDelta takeChanges();
  std::size_t vertexCount() const;
  // "" or the first broken internal invariant (a triangle on a freed vertex slot, ...).
  std::string validate() const;
  std::size_t triangleCount() const;

  // Bytes the updater holds, by structure (capacity, not just use).
  struct Memory {
    std::size_t cellBricks = 0;  // per cell brick with surface: fills read, owned edges, cells
    std::size_t triangles = 0;   // every cell brick's triangle lists
    std::size_t vertices = 0;    // per vertex slot: edge and parameter, position, normal, flags
    std::size_t loops = 0;       // loop centres' vertex lists
    std::size_t tables = 0;      // the dense table of cell bricks, free lists, scratch
    std::size_t total() const { return cellBricks + triangles + vertices + loops + tables; }
  };
  Memory memory() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace osteon::geometry
