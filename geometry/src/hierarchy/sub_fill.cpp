#include "sub_fill.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace osteon::geometry::detail {

// Splits `total` fill units over 64 sub-voxels in proportion to `weights`, exactly (largest
// remainder, ties to the lower index), none above a full sub-voxel. Even split without weight.
void distributeExactly(const std::array<std::uint8_t, kSubVoxels>* weights, Fill total,
                       std::array<Fill, kSubVoxels>& out) {
  unsigned weightSum = 0;
  if (weights) {
    for (std::uint8_t w : *weights) weightSum += w;
  }
  std::array<double, kSubVoxels> remainder{};
  unsigned assigned = 0;
  for (int i = 0; i < kSubVoxels; ++i) {
    const double ideal = weightSum > 0 ? double(total) * (*weights)[std::size_t(i)] / weightSum
                                       : double(total) / kSubVoxels;
    const double whole = std::min(std::floor(ideal), double(kSubFull));
    out[std::size_t(i)] = Fill(whole);
    remainder[std::size_t(i)] = ideal - whole;
    assigned += out[std::size_t(i)];
  }
  std::array<int, kSubVoxels> order;
  for (int i = 0; i < kSubVoxels; ++i) order[std::size_t(i)] = i;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return remainder[std::size_t(a)] > remainder[std::size_t(b)];
  });
  // Hand out what is left one unit at a time: first by largest remainder, then wherever
  // there is room (a capped sub-voxel pushes its share on).
  while (assigned < total) {
    for (int k = 0; k < kSubVoxels && assigned < total; ++k) {
      Fill& f = out[std::size_t(order[std::size_t(k)])];
      if (f < kSubFull) {
        ++f;
        ++assigned;
      }
    }
  }
}

// Sub-voxel fills from the mesh's sampling, adjusted to sum exactly to `total` (the parent,
// sampled with fewer rays, differs by a few percent). The difference goes to the sub-voxels
// the surface passes through, in proportion to f (255 - f), so sub-voxels the sampling saw
// as full stay full and empty ones stay empty whenever the surface ones can absorb it.
void fitToTotal(const std::array<std::uint8_t, kSubVoxels>& sampled, Fill total,
                std::array<Fill, kSubVoxels>& out) {
  long long sum = 0;
  for (int i = 0; i < kSubVoxels; ++i) {
    out[std::size_t(i)] = sampled[std::size_t(i)];
    sum += sampled[std::size_t(i)];
  }
  if (sum == 0) {
    distributeExactly(nullptr, total, out);
    return;
  }
  long long delta = (long long)total - sum;
  const int sign = delta > 0 ? 1 : -1;
  std::array<double, kSubVoxels> weight{};
  for (int pass = 0; delta != 0 && pass < 2; ++pass) {
    double weightSum = 0.0;
    for (int i = 0; i < kSubVoxels; ++i) {
      const double f = out[std::size_t(i)];
      const double room = sign > 0 ? kSubFull - f : f;
      // First pass: surface sub-voxels only; second: anything with room.
      weight[std::size_t(i)] = pass == 0 ? f * (kSubFull - f) : room;
      weightSum += weight[std::size_t(i)];
    }
    if (weightSum == 0.0) continue;
    const long long want = delta;
    std::array<double, kSubVoxels> remainder{};
    for (int i = 0; i < kSubVoxels && delta != 0; ++i) {
      const double share = double(std::llabs(want)) * weight[std::size_t(i)] / weightSum;
      const double room = sign > 0 ? kSubFull - out[std::size_t(i)] : out[std::size_t(i)];
      const long long whole = std::min<long long>((long long)std::floor(share), (long long)room);
      out[std::size_t(i)] = Fill(out[std::size_t(i)] + sign * whole);
      delta -= sign * whole;
      remainder[std::size_t(i)] = share - std::floor(share);
    }
    // The leftover units, one each, by largest remainder among those with weight and room.
    std::array<int, kSubVoxels> order;
    for (int i = 0; i < kSubVoxels; ++i) order[std::size_t(i)] = i;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return remainder[std::size_t(a)] > remainder[std::size_t(b)];
    });
    for (bool progress = true; delta != 0 && progress;) {
      progress = false;
      for (int k = 0; k < kSubVoxels && delta != 0; ++k) {
        const std::size_t i = std::size_t(order[std::size_t(k)]);
        const bool room = sign > 0 ? out[i] < kSubFull : out[i] > 0;
        if (weight[i] > 0.0 && room) {
          out[i] = Fill(out[i] + sign);
          delta -= sign;
          progress = true;
        }
      }
    }
  }
}

}  // namespace osteon::geometry::detail
