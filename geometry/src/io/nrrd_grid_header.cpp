// Reading the header of osteon's own grids (nrrd_grid_header.h): the value type, spacing and
// origin from the standard fields or osteon's exact keys, checked together.
#include "io/nrrd_grid_header.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <vector>

#include "io/nrrd_header.h"
#include "osteon/core/number_text.h"
#include "osteon/geometry/io/mesh_io.h"

namespace osteon::geometry::nrrd {

namespace {

bool nearlyEqual(double a, double b, double scale) {
  return std::abs(a - b) <= 1e-6 * scale;
}

// The stored value's width, refusing any type but the one `expected` (fill: uint8 or uint16;
// density: int16).
std::size_t valueBytesOf(const Header& nh, GridValue expected) {
  const std::string type = normaliseWords(nh.require("type", "type"));
  const std::optional<Scalar> scalar = scalarNamed(type);
  const std::string stored = scalar ? scalar->name : "";
  if (expected == GridValue::Fill) {
    // uint8 holds the voxelizer's 1/255 steps; uint16 the full fill units (1/16320).
    if (stored != "uint8" && stored != "uint16") {
      nh.fail("type " + excerpt(type) + " is not supported (fill must be uint8 or uint16)");
    }
  } else if (stored != "int16") {
    nh.fail("type " + excerpt(type) + " is not supported (density must be int16)");
  }
  return scalar->bytes;
}

// Where the grid's spacing and origin came from, for the messages that check them.
struct GeometrySource {
  bool haveSpacing = false;
  bool haveOrigin = false;
  const char* spacingField = "";
  const char* originField = "";
  glm::dvec3 originAsGiven{0.0};  // the field's value: voxel (0,0,0)'s centre or corner
};

// Spacing and origin from the standard fields: LPS, axis-aligned, positive, cubic voxels.
void readStandardGeometry(const Header& nh, GridHeader& h, GeometrySource& g) {
  if (const std::string* space = nh.field("space")) {
    const std::string s = normaliseWords(*space);
    if (s != "left-posterior-superior" && s != "lps") {
      nh.fail("space " + excerpt(s) + " is not supported (need left-posterior-superior)");
    }
  }
  if (const std::string* dirs = nh.field("spacedirections")) {
    std::vector<double> m;
    if (!parseNumbers(*dirs, m) || m.size() != 9) {
      nh.fail("space directions " + excerpt(*dirs) + " are not three 3-vectors");
    }
    const double scale = std::max({std::abs(m[0]), std::abs(m[4]), std::abs(m[8])});
    for (std::size_t r = 0; r < 3; ++r) {
      for (std::size_t c = 0; c < 3; ++c) {
        if (r != c && !nearlyEqual(m[r * 3 + c], 0.0, scale)) {
          nh.fail("space directions " + excerpt(*dirs) +
                  " are not axis-aligned (rotated grids are not supported)");
        }
      }
      if (!(m[r * 4] > 0.0)) {
        nh.fail("space directions " + excerpt(*dirs) + " have a non-positive axis");
      }
    }
    if (!nearlyEqual(m[0], m[4], scale) || !nearlyEqual(m[0], m[8], scale)) {
      nh.fail("anisotropic spacing " + excerpt(*dirs) + " is not supported (voxels must be cubes)");
    }
    h.voxelSizeMm = (m[0] + m[4] + m[8]) / 3.0;
    g.haveSpacing = true;
    g.spacingField = "space directions";
    if (const std::string* origin = nh.field("spaceorigin")) {
      std::vector<double> o;
      if (!parseNumbers(*origin, o) || o.size() != 3) {
        nh.fail("space origin " + excerpt(*origin) + " is not a 3-vector");
      }
      h.originMm = glm::dvec3(o[0], o[1], o[2]) - 0.5 * h.voxelSizeMm;
      g.haveOrigin = true;
      g.originField = "space origin";
      g.originAsGiven = glm::dvec3(o[0], o[1], o[2]);
    }
  } else if (const std::string* spacings = nh.field("spacings")) {
    std::vector<double> s;
    if (!parseNumbers(*spacings, s) || s.size() != 3 || !(s[0] > 0) || !(s[1] > 0) || !(s[2] > 0)) {
      nh.fail("spacings " + excerpt(*spacings) + " are not three positive numbers");
    }
    if (!nearlyEqual(s[0], s[1], s[0]) || !nearlyEqual(s[0], s[2], s[0])) {
      nh.fail("anisotropic spacing " + excerpt(*spacings) +
              " is not supported (voxels must be cubes)");
    }
    h.voxelSizeMm = (s[0] + s[1] + s[2]) / 3.0;
    g.haveSpacing = true;
    g.spacingField = "spacings";
  }
}

// osteon's own keys carry the exact doubles; the standard fields, when present, must agree.
void readOsteonGeometry(const Header& nh, GridHeader& h, GeometrySource& g) {
  const std::map<std::string, std::string>& keys = nh.keys;
  if (const auto it = keys.find("osteon_voxel_size_mm"); it != keys.end()) {
    double vs;
    if (!parseNumber(trim(it->second), vs) || vs <= 0.0) {
      nh.fail("osteon_voxel_size_mm is not a positive number");
    }
    if (g.haveSpacing && !nearlyEqual(vs, h.voxelSizeMm, vs)) {
      nh.fail("osteon_voxel_size_mm disagrees with the spacing fields");
    }
    h.voxelSizeMm = vs;
    g.haveSpacing = true;
    g.spacingField = "osteon_voxel_size_mm";
  }
  if (const auto it = keys.find("osteon_origin_mm"); it != keys.end()) {
    std::vector<double> o;
    if (!parseNumbers(it->second, o) || o.size() != 3) {
      nh.fail("osteon_origin_mm is not three numbers");
    }
    const glm::dvec3 origin(o[0], o[1], o[2]);
    for (int a = 0; a < 3; ++a) {
      if (g.haveOrigin && !nearlyEqual(origin[a], h.originMm[a], h.voxelSizeMm)) {
        nh.fail("osteon_origin_mm disagrees with the space origin field");
      }
    }
    h.originMm = origin;
    g.originField = "osteon_origin_mm";
    g.originAsGiven = origin;
  }
}

// Checked once combined: each field alone can be finite while the grid reaches infinity.
void checkGeometry(const Header& nh, const GridHeader& h, const GeometrySource& g) {
  if (!g.haveSpacing) nh.fail("no spacing ('space directions' or 'spacings' field)");
  const std::string spacingFrom = std::string("from '") + g.spacingField + "'";
  if (!std::isfinite(h.voxelSizeMm) || !(h.voxelSizeMm > 0.0)) {
    nh.fail("voxel size " + spacingFrom + " is not a positive finite number");
  }
  constexpr const char* kAxis[] = {"x", "y", "z"};
  const std::string beyond = " mm, beyond +-1e9 mm (1000 km)";
  for (int a = 0; a < 3; ++a) {
    if (!(std::abs(g.originAsGiven[a]) <= kMaxCoordinateMm)) {
      nh.fail(std::string("origin from '") + g.originField + "' is at " + kAxis[a] + " = " +
              numberText(g.originAsGiven[a]) + beyond);
    }
  }
  for (int a = 0; a < 3; ++a) {
    const double nearCorner = h.originMm[a];
    const double farCorner = h.originMm[a] + double(h.sizes[a]) * h.voxelSizeMm;
    const bool farOut = !(std::abs(farCorner) <= kMaxCoordinateMm);
    if (farOut || !(std::abs(nearCorner) <= kMaxCoordinateMm)) {
      nh.fail("voxel size " + numberText(h.voxelSizeMm) + " mm " + spacingFrom + " puts the " +
              (farOut ? "far" : "near") + " corner at " + kAxis[a] + " = " +
              numberText(farOut ? farCorner : nearCorner) + beyond);
    }
  }
}

// Parses and checks a header (nrrd_header.h reads it, as for every NRRD osteon opens); leaves
// `in` at the first data byte, wherever the header says the data lies.
}  // namespace

GridHeader readGridHeader(const std::string& path, std::ifstream& in, GridValue expected,
                          bool allowOutsideData) {
  const Header nh = readHeader(path);
  GridHeader h;
  h.sizes = readSizes(nh);
  const std::uint64_t voxels =
      std::uint64_t(h.sizes.x) * std::uint64_t(h.sizes.y) * std::uint64_t(h.sizes.z);
  h.valueBytes = valueBytesOf(nh, expected);
  const nrrd::Layout layout = readLayout(nh);
  if (layout.gzip) nh.fail("gzip encoding is not supported; save the volume uncompressed (raw)");
  h.bigEndian = layout.bigEndian;
  GeometrySource g;
  readStandardGeometry(nh, h, g);
  readOsteonGeometry(nh, h, g);
  checkGeometry(nh, h, g);
  // Before anything is allocated: the data must be exactly as long as the sizes say.
  const DataLocation at = locateData(nh, voxels * h.valueBytes, false, allowOutsideData);
  in = openData(at);
  h.dataShown = at.shown;
  return h;
}

}  // namespace osteon::geometry::nrrd
