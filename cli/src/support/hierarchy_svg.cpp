#include "support/hierarchy_svg.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_file.h"

namespace osteon::cli {

namespace {

const char* levelColour(int level) {
  static const char* colours[] = {"#d62728", "#e6b800", "#2ca02c", "#1f77b4",
                                  "#9467bd", "#8c564b", "#7f7f7f"};
  return colours[std::min(level, 6)];
}

}  // namespace

void writeHierarchySvg(const geometry::DynamicProximityHierarchy& hierarchy,
                       const geometry::VoxelGrid& grid, int sliceZ, const std::string& title,
                       const std::string& path) {
  const glm::ivec3 dims = grid.dims();
  const double px = std::max(2.0, 880.0 / std::max(dims.x, dims.y));  // pixels per voxel
  const double margin = 10.0;
  const double legend = 22.0 * (hierarchy.levelCount() + 1);
  const double width = dims.x * px + 2 * margin;
  const double height = dims.y * px + 2 * margin + legend;
  // Image y grows downwards; grid y (posterior) is drawn upwards so the view is from above.
  const auto sx = [&](double gx) { return margin + gx * px; };
  const auto sy = [&](double gy) { return margin + (dims.y - gy) * px; };

  std::ostringstream svg;
  svg.setf(std::ios::fixed);
  svg.precision(2);
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
      << "' viewBox='0 0 " << width << " " << height << "'>\n"
      << "<rect width='100%' height='100%' fill='white'/>\n"
      << "<clipPath id='grid'><rect x='" << margin << "' y='" << margin << "' width='"
      << dims.x * px << "' height='" << dims.y * px << "'/></clipPath>\n"
      << "<g clip-path='url(#grid)'>\n";
  // Level 0: the slice's voxels, opacity by fill.
  for (std::uint32_t i = 0; i < hierarchy.nodeSlots(0); ++i) {
    if (!hierarchy.alive(0, i)) continue;
    const glm::ivec3 v = hierarchy.centre(0, i);
    if (v.z != sliceZ) continue;
    const double fill = double(grid.fill(v)) / geometry::kFillFull;
    svg << "<rect x='" << sx(v.x) << "' y='" << sy(v.y + 1) << "' width='" << px << "' height='"
        << px << "' fill='" << levelColour(0) << "' fill-opacity='" << 0.25 + 0.6 * fill << "'/>\n";
  }
  // Levels above: cells crossing the slice, outlined, with their centres.
  for (int level = 1; level < hierarchy.levelCount(); ++level) {
    const long long half = hierarchy.halfWidth(level);
    for (std::uint32_t i = 0; i < hierarchy.nodeSlots(level); ++i) {
      if (!hierarchy.alive(level, i)) continue;
      const glm::ivec3 c = hierarchy.centre(level, i);
      if (std::llabs((long long)c.z - sliceZ) > half) continue;
      const double edge = double(2 * half + 1) * px;
      svg << "<rect x='" << sx(double(c.x - half)) << "' y='" << sy(double(c.y + half + 1))
          << "' width='" << edge << "' height='" << edge << "' fill='none' stroke='"
          << levelColour(level) << "' stroke-width='" << 0.6 + 0.5 * level << "'/>\n";
      svg << "<circle cx='" << sx(c.x + 0.5) << "' cy='" << sy(c.y + 0.5) << "' r='"
          << 1.0 + 0.6 * level << "' fill='" << levelColour(level) << "'/>\n";
    }
  }
  svg << "</g>\n<rect x='" << margin << "' y='" << margin << "' width='" << dims.x * px
      << "' height='" << dims.y * px << "' fill='none' stroke='#999'/>\n";
  // Legend, below the clipped drawing.
  double ly = dims.y * px + 2 * margin + 14;
  svg << "<text x='" << margin << "' y='" << ly << "' font-family='sans-serif' font-size='13'>"
      << title << " (slice z = " << sliceZ << ")</text>\n";
  for (int level = 0; level < hierarchy.levelCount(); ++level) {
    ly += 20;
    svg << "<rect x='" << margin << "' y='" << ly - 11 << "' width='12' height='12' fill='"
        << levelColour(level) << "'/><text x='" << margin + 18 << "' y='" << ly
        << "' font-family='sans-serif' font-size='12'>level " << level << ": "
        << hierarchy.nodeCount(level) << " nodes, cells of " << 2 * hierarchy.halfWidth(level) + 1
        << " voxels</text>\n";
  }
  svg << "</svg>\n";

  geometry::writeFileAtomically(path, svg.str());
}

}  // namespace osteon::cli
