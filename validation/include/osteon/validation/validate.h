// The nightly validation run (`osteon validate`): for each model x voxel size x surface method
// (crack-free, the seed's naive baseline) x force mode (static, dynamic with 2 levels), the
// surface is extracted and checked before drilling (exact checks, pixel cracks, accuracy),
// both portal paths are drilled with the collision cross-check, and the drilled surface is
// checked again. A guarantee broken by the crack-free method fails the run; the naive method
// is measured beside it, expected to break them.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/validation/collision_check.h"
#include "osteon/validation/crack_metric.h"
#include "osteon/validation/mesh_checks.h"

namespace osteon::validation {

// Forces at the base voxel size, or on voxels refined two levels near the tool.
enum class ForceMode { Static, Dynamic };
inline const char* forceModeName(ForceMode m) {
  return m == ForceMode::Static ? "static" : "dynamic";
}

struct ValidationModel {
  std::string name;             // as given: "default" or a path
  geometry::TriangleMesh mesh;  // in mm (empty for a volume)
  double loadScaleToMm = 1.0;   // how the file was scaled to mm (for messages)
  // A volume (an osteon grid, a label map, a CT): checked and drilled at its own voxel size
  // only, with no source polygons to measure accuracy against.
  std::optional<geometry::VoxelGrid> volume;
  // The voxel sizes this model runs at: the volume's own, or the options' for a mesh.
  std::vector<double> voxelSizesMm(const std::vector<double>& requested) const;
};

struct ValidationOptions {
  std::vector<double> voxelSizesMm{1.2, 0.9, 0.72, 0.54};
  int crackPixels = 512;
  int checkEverySteps = 10;  // collision cross-check period along the paths
  bool drill = true;
  // Indexes into caseGroups(models, options) (shard.h) to run, in ascending order; unset runs
  // every group. A shard of the nightly runs its own groups only.
  std::optional<std::vector<std::size_t>> groups;
};

struct PortalRun {
  std::string portal;
  CollisionCheckResult collisions;  // with the run's force log
  double maxForceN = 0.0;
  double jitterN = 0.0;
  std::uint64_t nonFiniteForces = 0;
};

struct ValidationCase {
  std::string model;
  double voxelSizeMm = 0.0;
  geometry::SurfaceMethod method = geometry::SurfaceMethod::CrackFree;
  ForceMode mode = ForceMode::Static;
  MeshReport before;
  CrackMetric cracks;
  Accuracy accuracy;
  bool accuracyKnown = false;
  double extractMs = 0.0;            // wall time of the whole extraction
  geometry::SurfaceTimings timings;  // its breakdown, as the seed's Table 2
  std::uint64_t voxels = 0;          // voxels at least half full, as the seed's Table 1
  std::size_t triangles = 0, vertices = 0;
  std::vector<PortalRun> portals;
  MeshReport after;  // the drilled surface (both portals drilled into one bone)
  CrackMetric afterCracks;
  // Wall time, for sizing runs (docs/validation.md): the group's set-up (voxelize, density,
  // head fit) shared by its four cases, the surface and its checks shared by the method's two
  // modes, and this case's own drilling with the drilled surface's checks.
  double setupMs = 0.0, surfaceMs = 0.0, drillMs = 0.0;
  std::vector<std::string> failures;  // broken guarantees, in words
  bool pass() const { return failures.empty(); }
};

struct ValidationReport {
  std::vector<ValidationCase> cases;
  // PASS when every crack-free case keeps every guarantee.
  bool pass() const;
};

ValidationReport runValidation(const std::vector<ValidationModel>& models,
                               const ValidationOptions& options,
                               const std::function<void(const ValidationCase&)>& progress = {});

}  // namespace osteon::validation
