// A voxelized bone written as other tools would write it: a label map (the label where a voxel
// is at least half bone) and a CT in HU (cortical 1300, cancellous 450, soft tissue -700), with
// seeded noise, for tests of the volume loaders, the CLI and the viewer.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "osteon/geometry/io/volume_io.h"
#include "osteon/geometry/voxels/voxel_grid.h"
#include "support/volume_files.h"

namespace osteon::test {

struct BoneVolumes {
  TestVolume geometry;  // sizes, spacing and first centre of the bone's grid (values empty)
  std::vector<double> labels, hu;
};

// partialVolume: a voxel's HU mixes bone and soft tissue in proportion to its fill, as a scanner
// averages what a voxel holds; otherwise each voxel is all bone or all tissue.
inline BoneVolumes boneVolumes(const geometry::VoxelGrid& bone, double label, double noiseHu,
                               unsigned seed, bool partialVolume) {
  BoneVolumes out;
  TestVolume& v = out.geometry;
  v.sizes = bone.dims();
  v.spacingMm = bone.voxelSizeMm();
  v.firstCentreMm = bone.voxelCentreMm(glm::ivec3(0));
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noiseHu);
  for (int z = 0; z < v.sizes.z; ++z) {
    for (int y = 0; y < v.sizes.y; ++y) {
      for (int x = 0; x < v.sizes.x; ++x) {
        geometry::Fill f;
        geometry::Density d;
        bone.fillAndDensity({x, y, z}, f, d);
        const bool in = f >= geometry::kFillHalf;
        out.labels.push_back(in ? label : 0.0);
        const double boneHu = d >= geometry::kCtCorticalDensity ? 1300.0 : 450.0;
        const double fraction =
            partialVolume ? double(f) / double(geometry::kFillFull) : (in ? 1.0 : 0.0);
        out.hu.push_back(std::round(-700.0 + fraction * (boneHu + 700.0) + noise(rng)));
      }
    }
  }
  return out;
}

}  // namespace osteon::test
