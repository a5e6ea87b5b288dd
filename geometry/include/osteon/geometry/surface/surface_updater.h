// The crack-free surface kept up to date as bone is drilled: after a change, only the cell
// bricks that read changed voxels are extracted again, and only the vertices within the
// smoothing's reach of the change are smoothed again. The result equals a full extraction of
// the new grid (same triangles, vertex positions to rounding).
#pragma once

#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxel_grid.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace osteon::geometry {

class SurfaceUpdater {
 public:
  struct UpdateStats {
    std::size_t cellBricks = 0;        // cell bricks extracted again
    std::size_t verticesTouched = 0;   // created, moved by their edge, or with new triangles
    std::size_t verticesSmoothed = 0;  // positions recomputed
    double ms = 0.0;         // all of the update
    double extractMs = 0.0;  // edges and triangles of the changed cells
    double smoothMs = 0.0;   // smoothing and normals
  };

  // Extracts the whole surface of `grid` (always the crack-free method; options.method is
  // ignored). The grid must outlive the updater. Throws InputError for bad options.
  SurfaceUpdater(const VoxelGrid& grid, const SurfaceOptions& options = {});
  ~SurfaceUpdater();
  SurfaceUpdater(const SurfaceUpdater&) = delete;
  SurfaceUpdater& operator=(const SurfaceUpdater&) = delete;

  // Brings the surface up to date after the voxels of these grid bricks changed (for example
  // grid.dirtyBricks(), then grid.clearDirty()).
  UpdateStats update(const std::vector<std::size_t>& changedGridBricks);

  // The current surface as compact arrays, triangles grouped by cell brick.
  SurfaceMesh mesh() const;
  std::size_t vertexCount() const;
  // "" or the first broken internal invariant (a triangle on a freed vertex slot, ...).
  std::string validate() const;
  std::size_t triangleCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace osteon::geometry
