#include "osteon/validation/shard.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/surface/surface.h"

namespace osteon::validation {

namespace {

// Voxels inside a model at a voxel size, without voxelizing: the enclosed volume over a voxel's,
// or the bounding box's for a mesh whose volume is not positive (open or inside out). A volume
// input runs at its own size only, so its own count is exact.
double estimateVoxels(const ValidationModel& model, double voxelSizeMm) {
  if (model.volume) return static_cast<double>(model.volume->countVoxels(geometry::kFillHalf));
  if (model.mesh.triangleCount() == 0) return 0.0;
  const double voxelMm3 = voxelSizeMm * voxelSizeMm * voxelSizeMm;
  const double volumeMm3 = geometry::signedVolumeMm3(model.mesh);
  if (volumeMm3 > voxelMm3) return volumeMm3 / voxelMm3;
  const glm::dvec3 extent = geometry::bounds(model.mesh).extentMm();
  return std::max(1.0, extent.x * extent.y * extent.z / voxelMm3);
}

}  // namespace

std::vector<CaseGroup> caseGroups(const std::vector<ValidationModel>& models,
                                  const ValidationOptions& options) {
  std::vector<CaseGroup> groups;
  for (std::size_t m = 0; m < models.size(); ++m) {
    for (const double voxelMm : models[m].voxelSizesMm(options.voxelSizesMm)) {
      CaseGroup g;
      g.model = m;
      g.voxelSizeMm = voxelMm;
      g.estimatedVoxels = estimateVoxels(models[m], voxelMm);
      // Every group holds the same four case kinds, so their weights (1 each) scale all groups
      // alike and only the voxels set them apart.
      g.cost = g.estimatedVoxels * kCasesPerGroup;
      groups.push_back(g);
    }
  }
  return groups;
}

std::string caseKey(const std::string& model, double voxelSizeMm, const std::string& method,
                    const std::string& mode) {
  std::ostringstream s;
  s << model << "|" << voxelSizeMm << "|" << method << "|" << mode;
  return s.str();
}

std::vector<std::string> caseKeys(const std::vector<ValidationModel>& models,
                                  const std::vector<CaseGroup>& groups) {
  std::vector<std::string> keys;
  for (const CaseGroup& g : groups) {
    for (const geometry::SurfaceMethod method :
         {geometry::SurfaceMethod::CrackFree, geometry::SurfaceMethod::Naive}) {
      for (const ForceMode mode : {ForceMode::Static, ForceMode::Dynamic}) {
        keys.push_back(caseKey(models[g.model].name, g.voxelSizeMm,
                               geometry::surfaceMethodName(method), forceModeName(mode)));
      }
    }
  }
  return keys;
}

std::vector<std::size_t> assignShards(const std::vector<double>& costs, std::size_t shardCount) {
  if (shardCount == 0) throw std::invalid_argument("assignShards: no shard to assign to");
  std::vector<std::size_t> order(costs.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return costs[a] > costs[b]; });
  std::vector<double> load(shardCount, 0.0);
  std::vector<std::size_t> shardOf(costs.size(), 0);
  for (const std::size_t i : order) {
    const std::size_t lightest =
        static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    shardOf[i] = lightest;
    load[lightest] += costs[i];
  }
  return shardOf;
}

}  // namespace osteon::validation
