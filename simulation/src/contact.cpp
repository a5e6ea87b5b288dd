#include "osteon/simulation/contact.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace osteon::simulation {

using geometry::VoxelSample;

namespace {

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The one definition of a part's shell: the samples whose centres lie farther than the inner
// layer from the core and not farther than the outer. fn(sample, toCore), toCore running from
// the sample's centre to the nearest point of the core.
template <typename Fn>
void forEachShellSample(geometry::RefinedVoxels& voxels, const ToolPart& part, const ToolPose& pose,
                        geometry::DphNearCache* cache, Fn&& fn) {
  const glm::dvec3 a = pose.toWorld(part.aMm), b = pose.toWorld(part.bMm);
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double invLen2 = len2 > 0.0 ? 1.0 / len2 : 0.0;
  // A refined voxel wholly outside the shell (beyond the outer layer, or inside the inner
  // one, where the tool has cut) is not opened; d - h <= r_o and d + h > r_i compared
  // squared, without a square root.
  const auto open = [&](const glm::dvec3& c, double halfDiagonal) {
    const double t = std::clamp(glm::dot(c - a, ab) * invLen2, 0.0, 1.0);
    const glm::dvec3 toCore = a + t * ab - c;
    const double d2 = glm::dot(toCore, toCore);
    const double far = part.outerRadiusMm + halfDiagonal;
    const double near = part.innerRadiusMm - halfDiagonal;
    return d2 <= far * far && (near < 0.0 || d2 > near * near);
  };
  // One query around the part's core (a long shaft in a sphere query would visit every voxel
  // within half its length), which tests each sample against both layers.
  voxels.forEachSampleInShell(a, b, part.innerRadiusMm, part.outerRadiusMm, cache, open, fn);
}

}  // namespace

ForceModel::ForceModel(const Tool& tool, double finestVoxelMm, double baseVoxelMm,
                       bool cuttingPartsPush)
    : tool_(tool), finestVoxelMm_(finestVoxelMm), cuttingPartsPush_(cuttingPartsPush) {
  const double ratio = baseVoxelMm / finestVoxelMm;
  weightPerFill_ = ratio * ratio * ratio / double(geometry::kFillFull);
  const double cube = finestVoxelMm * finestVoxelMm * finestVoxelMm;
  const double unitVolume = tool.literalSeedCount ? 4.0 / 3.0 * M_PI * cube : cube;
  for (int p = 0; p < tool.partCount; ++p) {
    maxCount_[std::size_t(p)] = tool.parts[std::size_t(p)].shellVolumeMm3() / unitVolume;
  }
}

ContactCaches ForceModel::makeCaches(double skinMm, std::size_t sliceNodes,
                                     const geometry::RefinedVoxels& voxels) const {
  ContactCaches caches;
  for (int p = 0; p < tool_.partCount; ++p) {
    const ToolPart& part = tool_.parts[std::size_t(p)];
    caches.shell[std::size_t(p)] = voxels.makeNearCache(
        part.lengthMm(), voxels.shellReachMm(part.outerRadiusMm), skinMm, sliceNodes);
  }
  return caches;
}

ContactForce ForceModel::compute(geometry::RefinedVoxels& voxels, const ToolPose& pose,
                                 ContactCaches* caches) const {
  ContactForce out;
  glm::dvec3 total(0.0);
  for (int p = 0; p < tool_.partCount; ++p) {
    glm::dvec3 direction(0.0);
    double n = 0.0;
    forEachShellSample(voxels, tool_.parts[std::size_t(p)], pose,
                       caches ? &caches->shell[std::size_t(p)] : nullptr,
                       [&](const VoxelSample& s, const glm::dvec3& toCore) {
                         const double w = double(s.fill) * weightPerFill_;
                         direction += w * toCore;
                         n += w;
                         ++out.samples;
                         out.level = std::min(out.level, s.level);
                       });
    out.contactVoxels += n;
    const double len = glm::length(direction);
    if (n <= 0.0 || !(len > 1e-12 * n)) continue;  // no bone, or pushed equally from all sides
    if (!cuttingPartsPush_ && tool_.parts[std::size_t(p)].cuts) continue;
    const double magnitude = tool_.maxForceN * std::min(n / maxCount_[std::size_t(p)], 1.0);
    total += (magnitude / len) * direction;
  }
  const double magnitude = glm::length(total);
  if (!finite(total) || !std::isfinite(magnitude)) {
    out.nonFinite = true;
    return out;  // zero force
  }
  out.forceN = magnitude > tool_.maxForceN ? total * (tool_.maxForceN / magnitude) : total;
  out.magnitudeN = std::min(magnitude, tool_.maxForceN);
  return out;
}

std::vector<VoxelSample> ForceModel::shellSamples(geometry::RefinedVoxels& voxels,
                                                  const ToolPose& pose, int part) const {
  std::vector<VoxelSample> samples;
  forEachShellSample(voxels, tool_.parts[std::size_t(part)], pose, nullptr,
                     [&](const VoxelSample& s, const glm::dvec3&) { samples.push_back(s); });
  return samples;
}

}  // namespace osteon::simulation
