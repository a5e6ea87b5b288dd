#include "support/surface_grids.h"

namespace osteon::test {

geometry::SurfaceOptions smoothing(int passes, bool taubin) {
  using geometry::SurfaceOptions;
  SurfaceOptions o;
  o.smoothIterations = passes;
  o.taubin = taubin;
  return o;
}

const std::vector<std::pair<std::string, geometry::SurfaceOptions>>& smoothingVariants() {
  static const std::vector<std::pair<std::string, geometry::SurfaceOptions>> variants = {
      {"0 passes", smoothing(0)},
      {"2 passes", smoothing(2)},
      {"10 passes", smoothing(10)},
      {"Taubin 10 passes", smoothing(10, true)}};
  return variants;
}

geometry::VoxelGrid emptyGrid(glm::ivec3 dims, double voxelSizeMm) {
  return geometry::VoxelGrid(dims, glm::dvec3(0.0), voxelSizeMm);
}

void setFull(geometry::VoxelGrid& g, const glm::ivec3& v) {
  g.set(v, geometry::kFillFull, 1);
}

geometry::Fill cornerFill(bool inside, CornerFills mode, std::mt19937& rng) {
  using geometry::Fill;
  using geometry::kFillFull;
  using geometry::kFillHalf;
  switch (mode) {
    case CornerFills::Binary:
      return inside ? kFillFull : Fill(0);
    case CornerFills::Random:
      return inside ? Fill(std::uniform_int_distribution<int>(kFillHalf, kFillFull)(rng))
                    : Fill(std::uniform_int_distribution<int>(0, kFillHalf - 1)(rng));
    case CornerFills::Extreme: {
      const bool far = std::uniform_int_distribution<int>(0, 1)(rng) == 1;
      return inside ? (far ? kFillFull : kFillHalf) : (far ? Fill(0) : Fill(kFillHalf - 1));
    }
  }
  return 0;
}

geometry::VoxelGrid singleCubeGrid(int config, geometry::Fill background, CornerFills mode,
                                   std::mt19937& rng) {
  geometry::VoxelGrid g = emptyGrid({4, 4, 4});
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) g.set({x, y, z}, background, 1);
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 v(1 + (c & 1), 1 + ((c >> 1) & 1), 1 + ((c >> 2) & 1));
    g.set(v, cornerFill(((config >> c) & 1) != 0, mode, rng), 1);
  }
  return g;
}

geometry::VoxelGrid noiseGrid(int n, std::uint32_t seed, double voxelSizeMm) {
  std::mt19937 rng(seed * 7919u + std::uint32_t(n));
  geometry::VoxelGrid g = emptyGrid({n, n, n}, voxelSizeMm);
  std::uniform_int_distribution<int> fill(0, geometry::kFillFull);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) g.set({x, y, z}, geometry::Fill(fill(rng)), 1);
  return g;
}

geometry::VoxelGrid extremeNoiseGrid(int n, std::uint32_t seed) {
  const geometry::Fill values[4] = {0, geometry::Fill(geometry::kFillHalf - 1), geometry::kFillHalf,
                                    geometry::kFillFull};
  std::mt19937 rng(seed);
  geometry::VoxelGrid g = emptyGrid({n, n, n});
  std::uniform_int_distribution<int> pick(0, 3);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) g.set({x, y, z}, values[pick(rng)], 1);
  return g;
}

}  // namespace osteon::test
