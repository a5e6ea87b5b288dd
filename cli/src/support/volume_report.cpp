#include "support/volume_report.h"

#include <sstream>

namespace osteon::cli {

namespace geo = osteon::geometry;
using nlohmann::json;

json volumeJson(const geo::VolumeLoad& v, const geo::VolumeOptions& meaning) {
  json j = {{"kind", v.kind}, {"format", v.format}, {"type", v.type}};
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
  } else {
    j["iso_hu"] = v.isoHu;
    j["iso_default"] = !meaning.isoHu.has_value();
    j["fill_ramp_hu"] = {v.isoHu - geo::kCtRampHalfWidthHu, v.isoHu + geo::kCtRampHalfWidthHu};
    j["cortical_from_hu"] = geo::kCorticalHu;
  }
  return j;
}

std::string volumeLine(const geo::VolumeLoad& v, const geo::VolumeOptions& meaning) {
  if (v.kind == "osteon grid") return "";  // osteon's own grids: the output as it always was
  std::ostringstream s;
  s << "  volume      " << v.format << " " << v.type << ", read as " << v.kind;
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
    s << " (values " << v.minValue << " to " << v.maxValue << "; iso " << v.isoHu << " HU"
      << (meaning.isoHu ? "" : " (default)") << ", cortical from " << geo::kCorticalHu << " HU)";
  }
  return s.str();
}

}  // namespace osteon::cli
