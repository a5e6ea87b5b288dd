#include "tool_view.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace osteon::viewer {

namespace sim = osteon::simulation;

namespace {

double distanceToSegmentMm(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

}  // namespace

double toolOffsetMm(const sim::Tool& tool, const sim::ToolPose& a, const sim::ToolPose& b) {
  double offset = glm::length(a.tipMm - b.tipMm);
  for (int i = 0; i < tool.partCount; ++i) {
    const sim::ToolPart& part = tool.parts[std::size_t(i)];
    offset = std::max(offset, glm::length(a.toWorld(part.aMm) - b.toWorld(part.aMm)));
    offset = std::max(offset, glm::length(a.toWorld(part.bMm) - b.toWorld(part.bMm)));
  }
  return offset;
}

bool showGhost(const sim::Tool& tool, const sim::ToolPose& proxy, const sim::ToolPose& commanded,
               double thresholdMm) {
  return toolOffsetMm(tool, proxy, commanded) > thresholdMm;
}

double boneDepthMm(const geometry::VoxelGrid& grid, const sim::Tool& tool,
                   const sim::ToolPose& pose) {
  double deepest = 0.0;
  const double vs = grid.voxelSizeMm();
  const glm::dvec3 f = pose.forward();
  for (int i = 0; i < tool.partCount; ++i) {
    const sim::ToolPart& part = tool.parts[std::size_t(i)];
    const double r = part.innerRadiusMm;
    const glm::dvec3 a = pose.toWorld(part.aMm), b = pose.toWorld(part.bMm);
    const double frontMm =
        std::max(glm::dot(a, f), glm::dot(b, f));  // the part's foremost core point
    // The voxels whose centres can lie within r of the segment.
    const glm::ivec3 lo =
        glm::max(grid.voxelFromWorld(glm::min(a, b) - r - 0.5 * vs), glm::ivec3(0));
    const glm::ivec3 hi =
        glm::min(grid.voxelFromWorld(glm::max(a, b) + r + 0.5 * vs), grid.dims() - 1);
    glm::ivec3 v;
    for (v.z = lo.z; v.z <= hi.z; ++v.z) {
      for (v.y = lo.y; v.y <= hi.y; ++v.y) {
        for (v.x = lo.x; v.x <= hi.x; ++v.x) {
          const glm::dvec3 p = grid.voxelCentreMm(v);
          if (distanceToSegmentMm(p, a, b) >= r) continue;
          // Backed out by t, the front cap clears p once (along - (front - t)) >= sqrt(r^2 -
          // rho^2).
          const double along = glm::dot(p, f);
          const double rho = glm::length((p - a) - glm::dot(p - a, f) * f);
          const double t = std::sqrt(std::max(r * r - rho * rho, 0.0)) + frontMm - along;
          if (t > deepest && grid.fill(v) >= geometry::kFillHalf) deepest = t;
        }
      }
    }
  }
  return deepest;
}

void ToolViewTally::add(const sim::Tool& tool, const sim::ToolPose& proxy,
                        const sim::ToolPose& commanded, double gapMm,
                        const geometry::VoxelGrid* grid) {
  ghostLast = showGhost(tool, proxy, commanded);
  ghostFrames += ghostLast ? 1 : 0;
  gapLastMm = gapMm;
  if (!grid) return;
  const double proxyMm = boneDepthMm(*grid, tool, proxy);
  // Poses within the ghost's threshold (always, under direct coupling) share one walk.
  const double commandedMm = ghostLast ? boneDepthMm(*grid, tool, commanded) : proxyMm;
  maxProxyDepthMm = std::max(maxProxyDepthMm, proxyMm);
  maxCommandedDepthMm = std::max(maxCommandedDepthMm, commandedMm);
}

}  // namespace osteon::viewer
