// The bone a session drills (BoneModel): built from a mesh (voxelized, the fine fills sampled)
// or a grid, with the head fitted on first use; and the estimate that refuses a session this
// machine cannot hold.
#include <algorithm>
#include <cmath>
#include <sstream>

#include <glm/geometric.hpp>

#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/core/option_error.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/hierarchy/fine_fill.h"
#include "osteon/geometry/io/units.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/session.h"

namespace osteon::simulation {

double estimateSessionBytes(const geometry::TriangleMesh& meshMm, double voxelSizeMm) {
  double areaMm2 = 0.0, volumeMm3 = 0.0;
  for (const glm::u32vec3& t : meshMm.triangles) {
    const glm::dvec3 &a = meshMm.positionsMm[t.x], &b = meshMm.positionsMm[t.y],
                     &c = meshMm.positionsMm[t.z];
    areaMm2 += 0.5 * glm::length(glm::cross(b - a, c - a));
    volumeMm3 += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  // An open or inside-out mesh: its signed volume says little, its box bounds it.
  glm::dvec3 lo(0.0), hi(0.0);
  if (!meshMm.positionsMm.empty()) lo = hi = meshMm.positionsMm.front();
  for (const glm::dvec3& p : meshMm.positionsMm) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 e = hi - lo;
  volumeMm3 = std::min(std::abs(volumeMm3), e.x * e.y * e.z);
  // Per surface voxel (area / vs^2) and per bone voxel (volume / vs^3), fitted to the peak RSS
  // of `drill default` (levels 2) at 0.54, 0.3, 0.2 and 0.15 mm within 3 %; plus the process.
  constexpr double kBytesPerSurfaceVoxel = 1200.0, kBytesPerBoneVoxel = 11.5, kProcessBytes = 32e6;
  const double vs = voxelSizeMm;
  return kProcessBytes + kBytesPerSurfaceVoxel * areaMm2 / (vs * vs) +
         kBytesPerBoneVoxel * volumeMm3 / (vs * vs * vs);
}

BoneModel::~BoneModel() = default;

std::shared_ptr<BoneModel> BoneModel::build(geometry::TriangleMesh meshMm, double voxelSizeMm,
                                            const std::string& name, double loadScaleToMm,
                                            const geometry::VoxelizeOptions& voxelizing,
                                            bool sampleFineFills, bool forSession) {
  const Clock::time_point start = Clock::now();
  std::shared_ptr<BoneModel> bone(new BoneModel());
  bone->name_ = name;
  bone->mesh_ = std::move(meshMm);
  // Refused before voxelizing when this machine cannot hold the session (it used to run for a
  // minute and die of bad_alloc); a voxel size that is no number is the voxelizer's to name.
  if (forSession && std::isfinite(voxelSizeMm) && voxelSizeMm > 0.0) {
    const glm::dvec3 e = geometry::bounds(*bone->mesh_).extentMm();
    std::ostringstream what;
    what << name << ": a " << e.x << " x " << e.y << " x " << e.z << " mm mesh drilled at "
         << (voxelizing.voxelSizeGiven ? optionRef("voxelSizeMm") + " " : std::string("voxels of "))
         << voxelSizeMm << " mm";
    // A mesh in metres read as millimetres is the likelier mistake than a small machine.
    std::string advice = geometry::unitsAdvice(std::max({e.x, e.y, e.z}), loadScaleToMm);
    if (voxelizing.voxelSizeGiven)
      advice +=
          std::string(advice.empty() ? "" : "; ") + "use a larger " + optionRef("voxelSizeMm");
    refuseOverMemory(what.str(), estimateSessionBytes(*bone->mesh_, voxelSizeMm), advice);
  }
  geometry::VoxelizeOptions vo = voxelizing;
  vo.voxelSizeMm = voxelSizeMm;
  vo.requireInside = forSession;
  vo.meshName = name;
  vo.loadScaleToMm = loadScaleToMm;
  geometry::VoxelizeStats stats;
  bone->grid_ = geometry::voxelize(*bone->mesh_, vo, &stats);
  // The voxelizer times its own passes; density is its last one, reported apart.
  bone->setup_.densityMs = stats.densityMs;
  bone->setup_.voxelizeMs = std::max(0.0, stats.totalMs - stats.densityMs);
  if (sampleFineFills) {
    const Clock::time_point fineStart = Clock::now();
    // Level -2 fills sampled from the mesh once; the ray scene is needed only for that.
    const geometry::EmbreeScene scene(*bone->mesh_);
    bone->fineFills_ = std::make_unique<geometry::FineFillSource>(
        geometry::FineFillSource::sample(bone->grid_, *bone->mesh_, scene));
    bone->setup_.fineFillsMs = msSince(fineStart);
  }
  bone->setup_.totalMs = msSince(start);
  return bone;
}

std::shared_ptr<const BoneModel> BoneModel::fromMesh(geometry::TriangleMesh meshMm,
                                                     double voxelSizeMm, const std::string& name,
                                                     double loadScaleToMm,
                                                     const geometry::VoxelizeOptions& voxelizing,
                                                     bool sampleFineFills,
                                                     const std::optional<glm::dvec3>& up) {
  std::shared_ptr<BoneModel> bone =
      build(std::move(meshMm), voxelSizeMm, name, loadScaleToMm, voxelizing, sampleFineFills);
  bone->up_ = up;
  return bone;
}

std::shared_ptr<BoneModel> BoneModel::wrapGrid(geometry::VoxelGrid grid, const std::string& name,
                                               double loadMs) {
  std::shared_ptr<BoneModel> bone(new BoneModel());
  bone->name_ = name;
  bone->grid_ = std::move(grid);
  bone->grid_.clearDirty();
  bone->setup_.loadMs = loadMs;
  bone->setup_.totalMs = loadMs;
  return bone;
}

std::shared_ptr<const BoneModel> BoneModel::fromGrid(geometry::VoxelGrid grid,
                                                     const std::string& name, double loadMs) {
  if (grid.countVoxels(geometry::kFillHalf) == 0) {
    throw InputError(name + ": the grid has no voxel inside (nothing to drill)");
  }
  return wrapGrid(std::move(grid), name, loadMs);
}

const geometry::TriangleMesh& BoneModel::headMesh() const {
  if (mesh_) return *mesh_;
  std::call_once(surfaceOnce_, [this] {
    // The grid as loaded (its half-fill surface: a CT's iso level), smoothed as `mesh` does;
    // the fit and the entry ray need positions and triangles only.
    geometry::SurfaceOptions options;
    options.computeNormals = false;
    surfaceMesh_ = geometry::extractSurface(grid_, options).toTriangleMesh();
  });
  return *surfaceMesh_;
}

const HumeralHead& BoneModel::humeralHead() const {
  const geometry::TriangleMesh& mesh = headMesh();
  // A grid's surface has thousands of points on every rounded end: the head is the largest cap.
  // A failed fit is kept as its message and thrown outside call_once: an exception through
  // call_once leaves the flag locked where pthread_once cannot unwind (TSan's interceptor).
  std::call_once(headOnce_, [this, &mesh] {
    HumeralHead head;
    try {
      head = fitHumeralHead(mesh, true, mesh_ ? HeadEnd::TightestSphere : HeadEnd::LargestCap, up_);
    } catch (const InputError& e) {
      headError_ = name_ + ": " + e.marked() + (mesh_ ? "" : " (fitted to the grid's surface)") +
                   "; give the up axis (" + optionRef("up") +
                   " x|y|z|-x|-y|-z) or an explicit entry point";
      return;
    }
    try {
      checkHumeralHead(head, name_);  // a sphere, but no humeral head: refused the same way
      head_ = head;
    } catch (const InputError& e) {
      headError_ = e.marked();
    }
  });
  if (!head_) throw InputError(headError_);
  return *head_;
}

std::shared_ptr<const BoneModel> BoneModel::open(const std::string& meshArgument, double scaleToMm,
                                                 double voxelSizeMm,
                                                 const geometry::VoxelizeOptions& voxelizing,
                                                 bool sampleFineFills) {
  BoneSource source;
  source.input = meshArgument;
  source.scale = scaleToMm;
  source.voxelSizeMm = voxelSizeMm;
  source.voxelizing = voxelizing;
  source.sampleFineFills = sampleFineFills;
  return open(source).bone;
}

}  // namespace osteon::simulation
