#include "bench_volumes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "osteon/geometry/voxels/voxelizer.h"

namespace osteon::bench {

using namespace osteon::geometry;

const HumerusModel& humerusModel() {
  static const HumerusModel m = buildHumerusModel();
  return m;
}

// An n^3 volume: the built-in humerus in the middle of it, or a sphere filling it with three
// drilled tunnels (straight cylinders of empty voxels).
const VoxelGrid& benchVolume(const std::string& name, int n) {
  static std::map<std::pair<std::string, int>, std::unique_ptr<VoxelGrid>> cache;
  auto& slot = cache[{name, n}];
  if (slot) return *slot;
  VoxelizeOptions options;
  if (name == "humerus") {
    // The bone voxelized so its longest side spans the box, then placed in the middle of an
    // n^3 volume, as a scan would hold it: the same n^3 voxels for both extractors.
    const Aabb box = bounds(humerusModel().mesh);
    const glm::dvec3 e = box.extentMm();
    options.voxelSizeMm = std::max({e.x, e.y, e.z}) / (n - 2);
    const VoxelGrid bone = voxelize(humerusModel().mesh, options);
    const glm::ivec3 shift = (glm::ivec3(n) - bone.dims()) / 2;
    slot = std::make_unique<VoxelGrid>(glm::ivec3(n),
                                       bone.originMm() - glm::dvec3(shift) * options.voxelSizeMm,
                                       options.voxelSizeMm);
    const glm::ivec3 d = bone.dims();
    for (int z = 0; z < d.z; ++z)
      for (int y = 0; y < d.y; ++y)
        for (int x = 0; x < d.x; ++x) {
          const Fill f = bone.fill({x, y, z});
          if (f != 0) slot->set(glm::ivec3(x, y, z) + shift, f, bone.density({x, y, z}));
        }
    slot->compact();
    slot->clearDirty();
    return *slot;
  }
  options.voxelSizeMm = 1.0;
  TriangleMesh sphere;
  {
    // UV sphere filling the n^3 box.
    const double r = 0.5 * (n - 3);
    const int slices = 256, stacks = 128;
    sphere.positionsMm.push_back({0, 0, r});
    for (int i = 1; i < stacks; ++i)
      for (int j = 0; j < slices; ++j) {
        const double th = M_PI * i / stacks, ph = 2 * M_PI * j / slices;
        sphere.positionsMm.push_back(
            r * glm::dvec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
      }
    sphere.positionsMm.push_back({0, 0, -r});
    const auto ring = [&](int i, int j) {
      return std::uint32_t(1 + (i - 1) * slices + (j % slices));
    };
    const auto south = std::uint32_t(sphere.positionsMm.size() - 1);
    for (int j = 0; j < slices; ++j) sphere.triangles.push_back({0u, ring(1, j), ring(1, j + 1)});
    for (int i = 1; i + 1 < stacks; ++i)
      for (int j = 0; j < slices; ++j) {
        sphere.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
        sphere.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
      }
    for (int j = 0; j < slices; ++j)
      sphere.triangles.push_back({south, ring(stacks - 1, j + 1), ring(stacks - 1, j)});
  }
  slot = std::make_unique<VoxelGrid>(voxelize(sphere, options));
  VoxelGrid& g = *slot;
  const glm::ivec3 d = g.dims();
  for (int axis = 0; axis < 3; ++axis) {  // three tunnels of radius n/12 through the centre
    const double radius = n / 12.0;
    for (int z = 0; z < d.z; ++z)
      for (int y = 0; y < d.y; ++y)
        for (int x = 0; x < d.x; ++x) {
          glm::dvec3 p = glm::dvec3(x, y, z) - glm::dvec3(d) * 0.5 + 0.5;
          p[axis] = 0.0;
          p[(axis + 1) % 3] -= n / 8.0;  // off centre, so they do not all meet
          if (glm::length(p) < radius) g.set({x, y, z}, 0, 0);
        }
  }
  g.compact();
  g.clearDirty();
  return g;
}

}  // namespace osteon::bench
