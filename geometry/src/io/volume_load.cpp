// What a volume's voxels mean (volume_io.h): a label map or a CT, decided from the values as
// stored (64-bit labels exact), then the grid built brick by brick.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <new>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/core/number_text.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/io/volume_io.h"

namespace osteon::geometry {

namespace {

// A malloc'd brick costs its arrays plus the allocator's header; the brick table 13 bytes a brick
// (pointer, uniform fill and density, dirty flag).
constexpr double kBrickBytes = double(sizeof(VoxelGrid::Brick)) + 16.0 + 13.0;

// Chessboard distance (in voxels) from each inside voxel to the nearest outside voxel or the
// volume's edge, by two raster passes over the 26-neighbourhood; 0 outside. It is at most half
// the smallest edge (below 1626 for 2^32 voxels), so 16 bits hold it.
template <typename Inside>
std::vector<std::uint16_t> insideDistance(glm::ivec3 n, Inside inside) {
  std::vector<std::uint16_t> d(std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z));
  const auto idx = [&](int x, int y, int z) {
    return (std::size_t(z) * std::size_t(n.y) + std::size_t(y)) * std::size_t(n.x) + std::size_t(x);
  };
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = inside(i) ? 0xffff : 0;
  const auto pass = [&](int sign) {
    for (int zz = 0; zz < n.z; ++zz) {
      const int z = sign > 0 ? zz : n.z - 1 - zz;
      for (int yy = 0; yy < n.y; ++yy) {
        const int y = sign > 0 ? yy : n.y - 1 - yy;
        for (int xx = 0; xx < n.x; ++xx) {
          const int x = sign > 0 ? xx : n.x - 1 - xx;
          std::uint16_t& here = d[idx(x, y, z)];
          if (here == 0) continue;
          int best = here;
          for (int dz = -1; dz <= 0; ++dz) {
            for (int dy = -1; dy <= 1; ++dy) {
              for (int dx = -1; dx <= 1; ++dx) {
                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                const int nx = x + sign * dx, ny = y + sign * dy, nz = z + sign * dz;
                const int e = (nx < 0 || ny < 0 || nz < 0 || nx >= n.x || ny >= n.y || nz >= n.z)
                                  ? 0
                                  : d[idx(nx, ny, nz)];
                best = std::min(best, e + 1);
              }
            }
          }
          here = std::uint16_t(best);
        }
      }
    }
  };
  pass(1);
  pass(-1);
  return d;
}

// Sets every voxel from voxel(index, fill, density), a brick at a time: bricks whose voxels all
// agree stay unallocated (a volume's air and deep bone cost no voxel arrays). Returns the voxels
// inside (fill at or above half).
template <typename Voxel>
std::uint64_t buildGrid(VoxelGrid& grid, Voxel voxel) {
  const glm::ivec3 n = grid.dims(), nb = grid.brickDims();
  std::array<Fill, kBrickVoxels> fill{};
  std::array<Density, kBrickVoxels> density{};
  std::uint64_t inside = 0;
  for (int bz = 0; bz < nb.z; ++bz) {
    for (int by = 0; by < nb.y; ++by) {
      for (int bx = 0; bx < nb.x; ++bx) {
        const glm::ivec3 lo(bx * kBrickEdge, by * kBrickEdge, bz * kBrickEdge);
        const glm::ivec3 hi = glm::min(lo + kBrickEdge, n);
        if (hi - lo !=
            glm::ivec3(kBrickEdge)) {  // a brick past the volume's edge: its padding empty
          fill.fill(0);
          density.fill(0);
        }
        bool uniform = true;  // compared with the brick's first voxel, local 0
        for (int z = lo.z; z < hi.z; ++z) {
          for (int y = lo.y; y < hi.y; ++y) {
            for (int x = lo.x; x < hi.x; ++x) {
              const std::size_t local =
                  std::size_t(VoxelGrid::voxelInBrick({x - lo.x, y - lo.y, z - lo.z}));
              voxel((std::size_t(z) * std::size_t(n.y) + std::size_t(y)) * std::size_t(n.x) +
                        std::size_t(x),
                    fill[local], density[local]);
              inside += fill[local] >= kFillHalf;
              uniform = uniform && fill[local] == fill[0] && density[local] == density[0];
            }
          }
        }
        const std::size_t brick = grid.brickIndex({bx, by, bz});
        if (uniform) {
          grid.setBrickUniform(brick, fill[0], density[0]);
          continue;
        }
        VoxelGrid::Brick& b = grid.materialiseBrick(brick);
        b.fill = fill;
        b.density = density;
      }
    }
  }
  grid.clearDirty();
  return inside;
}

// A volume whose every voxel is bone has no surface to drill: a misread volume, not a bone.
void refuseWholeBox(const std::string& path, std::uint64_t inside, std::uint64_t voxels,
                    const std::string& how) {
  if (inside < voxels) return;
  throw InputError(path + ": every voxel is bone: " + how +
                   "; not a plausible bone, which needs voxels outside it");
}

template <typename T>
void giveMeaning(const std::string& path, const RawVolume& raw, StoredValues<T> values,
                 const VolumeOptions& options, VolumeLoad& load) {
  const glm::ivec3 n = raw.sizes;
  const std::size_t count = std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z);
  // One pass: the range and, up to kMaxLabels + 1 of them, the distinct values and their counts
  // (runs of equal values counted at once: volumes are mostly runs).
  T lo = values[0], hi = lo;
  std::map<T, std::uint64_t> counts;
  T run = values[0];
  std::uint64_t runLength = 0;
  bool many = false;
  for (std::size_t i = 0; i < count; ++i) {
    const T x = values[i];
    lo = std::min(lo, x);
    hi = std::max(hi, x);
    if (x == run) {
      ++runLength;
    } else if (!many) {
      counts[run] += runLength;
      many = counts.size() > std::size_t(kMaxLabels);
      run = x;
      runLength = 1;
    }
  }
  if (!many) counts[run] += runLength;
  many = many || counts.size() > std::size_t(kMaxLabels);
  const auto real = [&raw](T x) {
    return raw.integer ? double(x) : double(x) * raw.slope + raw.intercept;
  };
  const double loReal = std::min(real(lo), real(hi)), hiReal = std::max(real(lo), real(hi));
  if (!std::isfinite(loReal) ||
      !std::isfinite(hiReal)) {  // finite stored values scaled past a double
    throw InputError(path + ": scl_slope " + numberText(raw.slope) + " and scl_inter " +
                     numberText(raw.intercept) + " scale values " + numberText(double(lo)) +
                     " to " + numberText(double(hi)) + " past any number");
  }
  load.minValue = loReal;
  load.maxValue = hiReal;
  bool negative = false;
  if constexpr (std::is_signed_v<T>) negative = lo < T(0);
  // Labels are never negative (HU are): negative values make a volume a CT or nothing, so a CT of
  // few values (air and bone) is not read as labels whose every non-zero voxel is bone.
  const bool labelMap = raw.integer && !many && !negative;
  const bool ct = !labelMap && raw.isSigned && hiReal - loReal >= kMinCtRangeHu;
  try {
    load.grid = VoxelGrid(n, raw.originMm, raw.voxelSizeMm);
  } catch (const std::invalid_argument& e) {
    throw InputError(path + ": " + e.what());
  }
  if (labelMap) {
    if (options.isoHu) {
      throw InputError(path + ": a label map (" + raw.type + ", " + std::to_string(counts.size()) +
                       " distinct values): --iso is for CTs; use --label");
    }
    load.kind = "label map";
    std::uint64_t mostCommon = 0, mostCount = 0;
    for (const auto& [value, c] : counts) {
      load.labels.push_back(std::uint64_t(value));
      if (c > mostCount) {
        mostCommon = std::uint64_t(value);
        mostCount = c;
      }
    }
    const bool zero = counts.count(T(0)) > 0;
    load.background = zero ? 0 : mostCommon;
    std::string found;
    for (std::uint64_t l : load.labels) found += (found.empty() ? "" : ", ") + std::to_string(l);
    if (options.label) {
      if (!std::binary_search(load.labels.begin(), load.labels.end(), *options.label)) {
        throw InputError(path + ": --label " + std::to_string(*options.label) +
                         " is not in the label map (labels found: " + found + ")");
      }
      load.label = options.label;
    }
    const std::uint64_t background = load.background;
    const std::optional<std::uint64_t> label = options.label;
    const std::vector<std::uint16_t> dist = insideDistance(n, [&](std::size_t i) {
      const std::uint64_t x = std::uint64_t(values[i]);
      return label ? x == *label : x != background;
    });
    const int shell =
        int(std::clamp(std::ceil(options.corticalThicknessMm / raw.voxelSizeMm), 1.0, 1e6));
    const std::uint64_t inside =
        buildGrid(load.grid, [&](std::size_t i, Fill& fill, Density& density) {
          fill = dist[i] ? kFillFull : 0;
          density = !dist[i] ? 0 : dist[i] <= shell ? kCtCorticalDensity : kCtCancellousDensity;
        });
    refuseWholeBox(path, inside, count,
                   "read as a label map (" + raw.type + ", labels " + found + "), bone = " +
                       (label ? "--label " + std::to_string(*label)
                              : "every voxel but the background " + std::to_string(background) +
                                    (zero ? "" : " (0 absent: the most common value)")));
  } else if (ct) {
    if (options.label) {
      throw InputError(path + ": a CT (" + raw.type + ", values " + numberText(loReal) + " to " +
                       numberText(hiReal) + "): --label is for label maps; use --iso");
    }
    load.kind = "ct";
    load.isoHu = options.isoHu.value_or(kDefaultIsoHu);
    const double iso = load.isoHu;
    const std::uint64_t inside =
        buildGrid(load.grid, [&](std::size_t i, Fill& fill, Density& density) {
          const double hu = real(values[i]);
          const double t = (hu - (iso - kCtRampHalfWidthHu)) / (2.0 * kCtRampHalfWidthHu);
          fill = Fill(std::lround(std::clamp(t, 0.0, 1.0) * kFillFull));
          density = fill == 0 ? 0 : hu >= kCorticalHu ? kCtCorticalDensity : kCtCancellousDensity;
        });
    refuseWholeBox(path, inside, count,
                   "read as a CT (" + raw.type + ", values " + numberText(loReal) + " to " +
                       numberText(hiReal) + " HU), all at or above the iso level " +
                       numberText(iso) + " HU" +
                       (options.isoHu ? " (--iso)" : " (the default; --iso sets it)"));
  } else {
    std::ostringstream s;
    s << path << ": neither a label map nor a CT: " << raw.type << ", values " << numberText(loReal)
      << " to " << numberText(hiReal) << ", "
      << (many ? "more than " + std::to_string(kMaxLabels) : std::to_string(counts.size()))
      << (counts.size() == 1 ? " distinct value" : " distinct values")
      << " (a label map is an integer type with at most " << kMaxLabels
      << " values, none negative; a CT a signed type spanning at least " << kMinCtRangeHu << " HU)";
    throw InputError(s.str());
  }
}

}  // namespace

double volumeLoadMemoryBytes(glm::ivec3 sizes, std::size_t scalarBytes) {
  const double voxels = double(sizes.x) * sizes.y * sizes.z;
  const auto bricksAlong = [](int n) { return std::ceil(double(n) / kBrickEdge); };
  const double bricks = bricksAlong(sizes.x) * bricksAlong(sizes.y) * bricksAlong(sizes.z);
  const double stored = voxels * double(scalarBytes);
  // Reading: the values and their copy in another axis order (flipped or permuted axes). gzip
  // data is inflated from 64 KiB pieces straight into the values; the 0.001 would still cover
  // the compressed data held whole (deflate grows data by at most 5 bytes in 16 KiB).
  const double reading = 2.001 * stored;
  // Meaning: the values, a label map's 16-bit distance per voxel, and the grid (every brick
  // allocated at worst).
  const double building = stored + 2.0 * voxels + bricks * kBrickBytes;
  // 4 MB beside: zlib's state, file buffers, the code the load runs first.
  return std::max(reading, building) + 4e6 + kVolumeLoadHeapSlackBytes + kVolumeLoadProcessBytes;
}

VolumeLoad loadVolume(const std::string& path, const VolumeOptions& options) {
  if (options.isoHu && !std::isfinite(*options.isoHu)) {
    throw InputError("--iso " + numberText(*options.isoHu) + ": must be a finite number of HU");
  }
  VolumeLoad load;
  load.format = volumeFormat(path);
  try {
    RawVolume raw = readRawVolume(path, options);
    if (raw.osteonGrid) {
      if (options.label || options.isoHu) {
        throw InputError(path + ": an osteon grid (fill and density as saved): " +
                         (options.label ? "--label" : "--iso") + " is for label maps and CTs");
      }
      NrrdReadResult r = readNrrd(path, options.allowOutsideData);
      load.grid = std::move(r.grid);
      load.densityLoaded = r.densityLoaded;
      load.kind = "osteon grid";
      load.type = "fill";
      return load;
    }
    load.type = raw.type;
    raw.visit([&](auto values) { giveMeaning(path, raw, values, options, load); });
  } catch (const std::bad_alloc&) {
    // The estimate (volumeLoadMemoryBytes) passed, yet memory ran out: other processes hold it.
    throw InputError(
        path +
        ": out of memory while loading the volume; crop or downsample it (fewer voxels), or "
        "free memory");
  }
  return load;
}

}  // namespace osteon::geometry
