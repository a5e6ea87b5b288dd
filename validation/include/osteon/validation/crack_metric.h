// The seed's pixel crack metric (section 3.4; docs/validation.md, "The seed's pixel crack
// metric"): the surface seen from the six axis directions at N x N pixels, orthographic and
// double-sided, front faces white, back faces red, background black;
// crack % = 100 red / (red + white). A red pixel is a ray that entered the surface through a
// hole and saw an inside. Rendered by Embree ray casting (no GPU), so the number is the same on
// every machine.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "osteon/geometry/io/mesh.h"

namespace osteon::validation {

struct CrackMetricOptions {
  int pixels = 512;         // N: each view is N x N
  bool keepImages = false;  // keep the RGB pixels of each view (for writeCrackImages)
};

struct CrackView {
  std::string name;  // "+x", "-x", ... : the side the surface is seen from
  std::uint64_t white = 0;
  std::uint64_t red = 0;
  std::vector<std::uint8_t> rgb;  // N x N x 3, top row first, when kept
};

struct CrackMetric {
  int pixels = 0;
  std::array<CrackView, 6> views;
  std::uint64_t white = 0;
  std::uint64_t red = 0;
  double crackPercent() const {
    return red + white > 0 ? 100.0 * double(red) / double(red + white) : 0.0;
  }
};

// Throws InputError for pixels outside 16..4096 or an empty mesh.
CrackMetric measureCracks(const geometry::TriangleMesh& mesh,
                          const CrackMetricOptions& options = {});

// Writes each kept view as DIR/cracks_<name>.png (OpenImageIO, through the osteon::image
// plugin, loaded here on first use); returns the paths. Throws InputError naming the file when
// it cannot be written or the plugin cannot be loaded, std::logic_error when no images were kept.
std::vector<std::string> writeCrackImages(const CrackMetric& metric, const std::string& dir);

}  // namespace osteon::validation
