// What a volume's voxels mean (volume_io.h): a label map, a CT or a scalar volume, decided from
// the values as stored (64-bit labels exact), then the grid built brick by brick where the
// volume lies (placed exactly or resampled, cropped or not).
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <new>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "io/volume_meaning.h"
#include "io/volume_sampling.h"
#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/core/number_text.h"
#include "osteon/core/option_error.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/io/volume_io.h"

namespace osteon::geometry {

namespace {

// A malloc'd brick costs its arrays plus the allocator's header; the brick table 13 bytes a brick
// (pointer, uniform fill and density, dirty flag).
constexpr double kBrickBytes = double(sizeof(VoxelGrid::Brick)) + 16.0 + 13.0;

// A label map's labels and background; refuses a label it does not hold.
// Returns the labels found, as text.
template <typename T>
std::string describeLabels(const std::string& path, const ValueSummary<T>& s,
                           const VolumeOptions& options, VolumeLoad& load) {
  load.kind = "label map";
  std::uint64_t mostCommon = 0, mostCount = 0;
  for (const auto& [value, c] : s.counts) {
    load.labels.push_back(std::uint64_t(value));
    if (c > mostCount) {
      mostCommon = std::uint64_t(value);
      mostCount = c;
    }
  }
  load.background = s.counts.count(T(0)) > 0 ? 0 : mostCommon;
  std::string found;
  for (std::uint64_t l : load.labels) found += (found.empty() ? "" : ", ") + std::to_string(l);
  const auto check = [&](const char* field, std::uint64_t label) {
    if (!std::binary_search(load.labels.begin(), load.labels.end(), label)) {
      throw InputError(path + ": " + optionRef(field) + " " + std::to_string(label) +
                       " is not in the label map (labels found: " + found + ")");
    }
  };
  if (options.label) check("volume.label", *options.label);
  if (options.cropToLabel) check("volume.cropToLabel", *options.cropToLabel);
  load.label = options.label;
  return found;
}

// The box a crop option asks for: cropMm as given, cropToLabel the label's voxels grown by the
// margin; none without either.
template <typename T>
std::optional<BoxMm> cropBox(const RawVolume& raw, StoredValues<T> values,
                             const VolumeOptions& options) {
  if (options.cropMm) return options.cropMm;
  if (!options.cropToLabel) return std::nullopt;
  const std::uint64_t label = *options.cropToLabel;
  const auto [lo, hi] =
      insideBounds(raw.sizes, values, [label](T x) { return std::uint64_t(x) == label; });
  BoxMm box = storedBoxMm(raw, lo, hi);
  box.minMm -= options.cropMarginMm;
  box.maxMm += options.cropMarginMm;
  return box;
}

void describeTransform(const RawVolume& raw, const OutputGrid& g, bool labels, bool cropped,
                       VolumeTransform& t) {
  t.storedSizes = raw.storedSizes;
  t.firstCentreMm = raw.firstCentreMm;
  for (int a = 0; a < 3; ++a) {
    t.spacingMm[a] = glm::length(raw.indexToLpsMm[a]);
    t.directions[a] = raw.indexToLpsMm[a] / t.spacingMm[a];
  }
  t.resampled = !g.exact;
  t.interpolation = g.exact ? "none" : labels ? "partial volume" : "trilinear";
  t.cropped = cropped;
}

template <typename T>
void giveMeaning(const std::string& path, const RawVolume& raw, StoredValues<T> values,
                 const VolumeOptions& options, VolumeLoad& load) {
  const glm::ivec3 n = raw.sizes;
  const std::size_t count = std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z);
  const ValueSummary<T> s = summarise(values, count);
  const auto real = [&raw](T x) {
    return raw.integer ? double(x) : double(x) * raw.slope + raw.intercept;
  };
  const double loReal = std::min(real(s.lo), real(s.hi)), hiReal = std::max(real(s.lo), real(s.hi));
  if (!std::isfinite(loReal) || !std::isfinite(hiReal)) {  // finite values scaled past a double
    throw InputError(path + ": scl_slope " + numberText(raw.slope) + " and scl_inter " +
                     numberText(raw.intercept) + " scale values " + numberText(double(s.lo)) +
                     " to " + numberText(double(s.hi)) + " past any number");
  }
  load.minValue = loReal;
  load.maxValue = hiReal;
  // An iso value given is the user's word that the values are levels: a quantised micro-CT or
  // a 0/1 mask saved as floats is then bone above it, not a label map.
  const bool labelMap = !options.isoValue && isLabelMap(s, raw);
  const bool ct = !labelMap && raw.isSigned && hiReal - loReal >= kMinCtRangeHu;
  const bool scalar = !labelMap && !ct && options.isoValue;
  const std::string valuesText =
      raw.type + ", values " + numberText(loReal) + " to " + numberText(hiReal);
  if (!labelMap && !ct && !scalar) {
    std::ostringstream m;
    m << path << ": neither a label map nor a CT: " << valuesText << ", "
      << (s.many ? "more than " + std::to_string(kMaxLabels) : std::to_string(s.counts.size()))
      << (s.counts.size() == 1 ? " distinct value" : " distinct values")
      << " (a label map has whole values, at most " << kMaxLabels
      << " of them, none negative; a CT is signed, spanning at least " << kMinCtRangeHu
      << " HU); " + optionRef("volume.isoValue") + " reads any volume as bone above that value";
    throw InputError(m.str());
  }
  std::string found;
  if (labelMap) found = describeLabels(path, s, options, load);
  if (!labelMap && options.label) {
    throw InputError(path + ": a " + (ct ? "CT" : "scalar volume") + " (" + valuesText +
                     "): " + optionRef("volume.label") + " is for label maps; use " +
                     optionRef("volume.isoValue"));
  }
  if (!labelMap && options.cropToLabel) {
    throw InputError(path + ": a " + (ct ? "CT" : "scalar volume") + " (" + valuesText +
                     "): " + optionRef("volume.cropToLabel") + " is for label maps; use " +
                     optionRef("volume.cropMm"));
  }
  const std::optional<BoxMm> crop = cropBox(raw, values, options);
  const OutputGrid g = planOutput(path, raw, options, crop);
  describeTransform(raw, g, labelMap, crop.has_value(), load.transform);
  try {
    load.grid = VoxelGrid(g.sizes, g.originMm, g.voxelSizeMm);
  } catch (const std::invalid_argument& e) {
    throw InputError(path + ": " + e.what());
  }
  const std::uint64_t voxels = g.count();
  if (labelMap) {
    const std::uint64_t background = load.background;
    const std::optional<std::uint64_t> label = options.label;
    // Compared in the stored type, by value and branch-free (the grid's rows test it voxel by
    // voxel, a vector at a time): the label or background is a stored value (or 0), so exact.
    const bool byLabel = label.has_value();
    const T named = T(label.value_or(background));
    const auto inside = [byLabel, named](T x) { return (x == named) == byLabel; };
    const std::uint64_t in = buildLabels(g, values, inside, options, load.grid);
    refuseWholeBox(path, in, voxels,
                   "read as a label map (" + raw.type + ", labels " + found + "), bone = " +
                       (label ? optionRef("volume.label") + " " + std::to_string(*label)
                              : "every voxel but the background " + std::to_string(background) +
                                    (background == 0 ? "" : " (0 absent: the most common value)")));
    return;
  }
  load.kind = ct ? "ct" : "scalar";
  load.isoValue = options.isoValue.value_or(kDefaultIsoHu);
  const double iso = load.isoValue;
  const std::string given = options.isoValue
                                ? " (" + optionRef("volume.isoValue") + ")"
                                : " (the default; " + optionRef("volume.isoValue") + " sets it)";
  if (ct) {
    load.rampHalfWidth = kCtRampHalfWidthHu;
    const std::uint64_t in = buildCt(g, values, real, loReal, iso, load.grid);
    refuseWholeBox(path, in, voxels,
                   "read as a CT (" + valuesText + " HU), all at or above the iso level " +
                       numberText(iso) + " HU" + given);
    return;
  }
  load.rampHalfWidth = kScalarRampHalfWidth * (hiReal - loReal);
  const std::uint64_t in =
      buildScalar(g, values, real, loReal, iso, load.rampHalfWidth, options, load.grid);
  refuseWholeBox(path, in, voxels,
                 "read as a scalar volume (" + valuesText + "), all at or above the iso value " +
                     numberText(iso) + given);
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
  // Meaning: the values, a label map's deep-inside byte per voxel, and the grid (every brick
  // allocated at worst).
  const double building = stored + 1.0 * voxels + bricks * kBrickBytes;
  // 4 MB beside: zlib's state, file buffers, the code the load runs first.
  return std::max(reading, building) + 4e6 + kVolumeLoadHeapSlackBytes + kVolumeLoadProcessBytes;
}

namespace {

// Every option's value checked before anything is read.
void checkOptions(const VolumeOptions& options) {
  if (options.isoValue && !std::isfinite(*options.isoValue)) {
    throw OptionError("volume.isoValue", numberText(*options.isoValue),
                      "must be a finite number (HU for a CT, else the volume's own units)");
  }
  // An iso value reads the values as levels, so nothing is left to pick labels from.
  if (options.isoValue && options.label) {
    throw OptionError("volume.label", std::to_string(*options.label),
                      "picks a label map's bone; " + optionRef("volume.isoValue") +
                          " reads the values as levels instead: give one of them");
  }
  if (options.isoValue && options.cropToLabel) {
    throw OptionError("volume.cropToLabel", std::to_string(*options.cropToLabel),
                      "needs labels; " + optionRef("volume.isoValue") +
                          " reads the values as levels: crop with " + optionRef("volume.cropMm"));
  }
  if (options.voxelSizeMm && !(std::isfinite(*options.voxelSizeMm) && *options.voxelSizeMm > 0)) {
    throw OptionError("volume.voxelSizeMm", numberText(*options.voxelSizeMm),
                      "must be a positive number of mm");
  }
  if (const auto& c = options.cropMm) {
    for (int a = 0; a < 3; ++a) {
      if (!(std::isfinite(c->minMm[a]) && std::isfinite(c->maxMm[a]) && c->minMm[a] < c->maxMm[a]))
        throw OptionError("volume.cropMm", "", "each axis's range must be finite, low below high");
    }
    if (options.cropToLabel) {
      throw OptionError("volume.cropToLabel", std::to_string(*options.cropToLabel),
                        "give a crop box or a label to crop to, not both");
    }
  }
  if (!(std::isfinite(options.cropMarginMm) && options.cropMarginMm >= 0)) {
    throw OptionError("volume.cropMarginMm", numberText(options.cropMarginMm),
                      "must be a number of mm, at least 0");
  }
}

}  // namespace

VolumeLoad loadVolume(const std::string& path, const VolumeOptions& options) {
  checkOptions(options);
  VolumeLoad load;
  load.format = volumeFormat(path);
  try {
    RawVolume raw = readRawVolume(path, options);
    if (raw.osteonGrid) {
      if (options.label || options.isoValue || options.cropMm || options.cropToLabel) {
        throw InputError(path + ": an osteon grid (fill and density as saved): " +
                         (options.label      ? optionRef("volume.label")
                          : options.isoValue ? optionRef("volume.isoValue")
                                             : "a crop") +
                         " is for label maps and CTs");
      }
      NrrdReadResult r = readNrrd(path, options.allowOutsideData);
      load.grid = std::move(r.grid);
      load.densityLoaded = r.densityLoaded;
      load.kind = "osteon grid";
      load.type = "fill";
      return load;
    }
    load.type = raw.type;
    load.seriesUid = raw.seriesUid;
    load.seriesDescription = raw.seriesDescription;
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
