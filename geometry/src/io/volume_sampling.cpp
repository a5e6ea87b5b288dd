// The grid a volume loads onto (volume_sampling.h): placed exactly, or resampled onto cubic
// axis-aligned LPS voxels covering the stored grid's box; either cut to a crop box.
#include "io/volume_sampling.h"

#include <cmath>

#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/core/number_text.h"
#include "osteon/core/option_error.h"

namespace osteon::geometry {

namespace {

std::string boxText(const BoxMm& b) {
  return numberText(b.minMm.x) + ":" + numberText(b.maxMm.x) + "," + numberText(b.minMm.y) + ":" +
         numberText(b.maxMm.y) + "," + numberText(b.minMm.z) + ":" + numberText(b.maxMm.z);
}

// Voxels of edge v from lowMm whose centres lie in [cropLo, cropHi], among n: [first, end).
std::pair<int, int> voxelsWithin(double lowMm, double v, int n, double cropLo, double cropHi) {
  const double first = std::ceil((cropLo - lowMm) / v - 0.5 - 1e-9);
  const double end = std::floor((cropHi - lowMm) / v - 0.5 + 1e-9) + 1.0;
  return {int(std::clamp(first, 0.0, double(n))), int(std::clamp(end, 0.0, double(n)))};
}

// A resampled grid too large: the voxel size's fault when one was given, else the volume's
// (its finest spacing).
[[noreturn]] void refuseResampling(const std::string& path, const VolumeOptions& options,
                                   double voxelMm, const std::string& what) {
  if (options.voxelSizeMm) {
    throw OptionError("volume.voxelSizeMm", numberText(voxelMm),
                      "resamples " + path + " to " + what + "; give a larger one or a crop");
  }
  throw InputError(path + ": resampled at its finest spacing, " + numberText(voxelMm) +
                   " mm, it would be " + what + "; give a larger " +
                   optionRef("volume.voxelSizeMm") + " or a " + optionRef("volume.cropMm"));
}

}  // namespace

BoxMm storedBoxMm(const RawVolume& raw, glm::ivec3 lo, glm::ivec3 hi) {
  if (!raw.resample) {
    return {raw.originMm + glm::dvec3(lo) * raw.voxelSizeMm,
            raw.originMm + glm::dvec3(hi + 1) * raw.voxelSizeMm};
  }
  BoxMm box{glm::dvec3(INFINITY), glm::dvec3(-INFINITY)};
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 index((corner & 1) ? hi.x + 0.5 : lo.x - 0.5,
                           (corner & 2) ? hi.y + 0.5 : lo.y - 0.5,
                           (corner & 4) ? hi.z + 0.5 : lo.z - 0.5);
    const glm::dvec3 p = raw.firstCentreMm + raw.indexToLpsMm * index;
    box.minMm = glm::min(box.minMm, p);
    box.maxMm = glm::max(box.maxMm, p);
  }
  return box;
}

OutputGrid planOutput(const std::string& path, const RawVolume& raw, const VolumeOptions& options,
                      const std::optional<BoxMm>& crop) {
  OutputGrid g;
  g.stored = raw.sizes;
  g.exact = !raw.resample;
  BoxMm box = storedBoxMm(raw, glm::ivec3(0), raw.sizes - 1);
  if (g.exact) {
    g.voxelSizeMm = raw.voxelSizeMm;
  } else {
    g.voxelSizeMm = options.voxelSizeMm.value_or(raw.voxelSizeMm);
    g.lpsToIndex = glm::inverse(raw.indexToLpsMm);
    g.firstCentreMm = raw.firstCentreMm;
  }
  glm::ivec3 first(0), end;
  for (int a = 0; a < 3; ++a) {
    const double extent = (box.maxMm[a] - box.minMm[a]) / g.voxelSizeMm;
    end[a] = g.exact ? raw.sizes[a] : int(std::max(1.0, std::ceil(extent - 1e-6)));
    if (!g.exact && !(extent < double(1 << 30))) {
      refuseResampling(path, options, g.voxelSizeMm, "more than 2^30 voxels along an axis");
    }
    if (crop) {
      std::tie(first[a], end[a]) =
          voxelsWithin(box.minMm[a], g.voxelSizeMm, end[a], crop->minMm[a], crop->maxMm[a]);
      if (first[a] >= end[a]) {
        throw InputError(path + ": the crop " + boxText(*crop) +
                         " mm holds no voxel of the volume, which spans " + boxText(box) + " mm");
      }
    }
  }
  g.sizes = end - first;
  g.offset = first;
  g.originMm = box.minMm + glm::dvec3(first) * g.voxelSizeMm;
  g.whole = g.exact && g.sizes == g.stored;
  if (g.exact) return g;
  g.offset = glm::ivec3(0);
  const double voxels = double(g.sizes.x) * double(g.sizes.y) * double(g.sizes.z);
  if (voxels > double(VoxelGrid::kMaxVoxels)) {
    refuseResampling(path, options, g.voxelSizeMm, numberText(voxels) + " voxels, more than 2^32");
  }
  // Spacings that differ a thousandfold are a corrupt header, not a scan (a clinical CT's slices
  // are at most some twenty times its pixels): resampling them unasked would take minutes.
  const double stored = double(g.stored.x) * double(g.stored.y) * double(g.stored.z);
  if (!options.voxelSizeMm && voxels > double(1 << 20) && voxels > 1000.0 * stored) {
    refuseResampling(path, options, g.voxelSizeMm,
                     numberText(voxels) + " voxels from " + numberText(stored) +
                         " stored (its spacings differ more than a thousandfold)");
  }
  // The stored values, a held fill and a deep-inside byte per voxel, the grid's bricks at worst
  // (about 4 bytes a voxel): 8 bytes a voxel covers them.
  refuseOverMemory(path + ": resampled at " + numberText(g.voxelSizeMm) + " mm",
                   double(raw.data.size()) + voxels * 8.0 + kVolumeLoadProcessBytes,
                   "give a larger voxel size or a crop");
  return g;
}

}  // namespace osteon::geometry
