#include "support/volume_report.h"

#include <sstream>

namespace osteon::cli {

namespace geo = osteon::geometry;
using nlohmann::json;

namespace {

json vectorJson(const glm::dvec3& v) {
  return json::array({v.x, v.y, v.z});
}

// How the stored grid became osteon's: its sizes, spacing, axes and first voxel as read, and
// whether it was resampled (and how) or cropped; the grid's own geometry beside it.
json transformJson(const geo::VolumeLoad& v) {
  const geo::VolumeTransform& t = v.transform;
  json directions = json::array();
  for (int a = 0; a < 3; ++a) directions.push_back(vectorJson(t.directions[a]));
  const glm::ivec3 dims = v.grid.dims();
  return {{"stored_sizes", {t.storedSizes.x, t.storedSizes.y, t.storedSizes.z}},
          {"spacing_mm", vectorJson(t.spacingMm)},
          {"directions_lps", directions},
          {"first_voxel_centre_mm", vectorJson(t.firstCentreMm)},
          {"resampled", t.resampled},
          {"interpolation", t.interpolation},
          {"cropped", t.cropped},
          {"sizes", {dims.x, dims.y, dims.z}},
          {"voxel_size_mm", v.grid.voxelSizeMm()},
          {"origin_mm", vectorJson(v.grid.originMm())}};
}

std::string transformLine(const geo::VolumeLoad& v) {
  const geo::VolumeTransform& t = v.transform;
  const glm::ivec3 dims = v.grid.dims();
  std::ostringstream s;
  s << "  transform   " << t.storedSizes.x << " x " << t.storedSizes.y << " x " << t.storedSizes.z
    << " voxels of " << t.spacingMm.x << " x " << t.spacingMm.y << " x " << t.spacingMm.z
    << " mm, axes (LPS)";
  for (int a = 0; a < 3; ++a) {
    s << " (" << t.directions[a].x << ", " << t.directions[a].y << ", " << t.directions[a].z << ")";
  }
  s << ", first voxel at (" << t.firstCentreMm.x << ", " << t.firstCentreMm.y << ", "
    << t.firstCentreMm.z << ") mm; "
    << (t.resampled ? "resampled (" + t.interpolation + ")" : std::string("placed as stored"))
    << (t.cropped ? ", cropped" : "") << " to " << dims.x << " x " << dims.y << " x " << dims.z
    << " voxels of " << v.grid.voxelSizeMm() << " mm from (" << v.grid.originMm().x << ", "
    << v.grid.originMm().y << ", " << v.grid.originMm().z << ") mm";
  return s.str();
}

}  // namespace

json volumeJson(const geo::VolumeLoad& v, const geo::VolumeOptions& meaning) {
  json j = {{"kind", v.kind}, {"format", v.format}, {"type", v.type}};
  if (!v.seriesUid.empty()) {
    j["series_uid"] = v.seriesUid;
    j["series_description"] = v.seriesDescription;
  }
  if (v.kind == "osteon grid") {
    j["density_loaded"] = v.densityLoaded;
    return j;
  }
  j["min"] = v.minValue;
  j["max"] = v.maxValue;
  if (v.kind == "label map") {
    // Labels as integers, exact to 64 bits (a uint64 label past 2^63 too), not as doubles.
    j["min"] = v.labels.front();
    j["max"] = v.labels.back();
    j["labels"] = v.labels;
    j["background"] = v.background;
    j["bone_label"] = v.label ? json(*v.label)
                              : json(v.background == 0 ? "every non-zero" : "every non-background");
  } else if (v.kind == "ct") {
    j["iso_hu"] = v.isoValue;
    j["iso_default"] = !meaning.isoValue.has_value();
    j["fill_ramp_hu"] = {v.isoValue - v.rampHalfWidth, v.isoValue + v.rampHalfWidth};
    j["cortical_from_hu"] = geo::kCorticalHu;
  } else {
    j["iso_value"] = v.isoValue;
    j["fill_ramp"] = {v.isoValue - v.rampHalfWidth, v.isoValue + v.rampHalfWidth};
    j["cortical_within_mm"] = meaning.corticalThicknessMm;
  }
  j["transform"] = transformJson(v);
  return j;
}

std::string volumeLine(const geo::VolumeLoad& v, const geo::VolumeOptions& meaning) {
  if (v.kind == "osteon grid") return "";  // osteon's own grids: the output as it always was
  std::ostringstream s;
  s << "  volume      " << v.format << " " << v.type;
  if (!v.seriesUid.empty()) {
    s << " series " << v.seriesUid
      << (v.seriesDescription.empty() ? "" : " (" + v.seriesDescription + ")");
  }
  s << ", read as " << v.kind;
  if (v.kind == "label map") {
    s << " (labels";
    for (std::uint64_t l : v.labels) s << " " << l;
    s << "; bone: "
      << (v.label             ? "label " + std::to_string(*v.label)
          : v.background == 0 ? std::string("every non-zero voxel")
                              : "every voxel but the background " + std::to_string(v.background) +
                                    " (0 absent: the most common value)")
      << ")";
  } else if (v.kind == "ct") {
    s << " (values " << v.minValue << " to " << v.maxValue << "; iso " << v.isoValue << " HU"
      << (meaning.isoValue ? "" : " (default)") << ", cortical from " << geo::kCorticalHu << " HU)";
  } else {
    s << " (values " << v.minValue << " to " << v.maxValue << "; bone above " << v.isoValue
      << ", fill ramped over +-" << v.rampHalfWidth << "; cortical within "
      << meaning.corticalThicknessMm << " mm of the surface)";
  }
  s << "\n" << transformLine(v);
  return s.str();
}

}  // namespace osteon::cli
