#include "support/output.h"

#include <cstdio>
#include <iostream>

#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/simulation/runner.h"
#include "osteon/simulation/session.h"

namespace osteon::cli {

using nlohmann::json;

json vec3Json(const glm::dvec3& v) {
  return json::array({v.x, v.y, v.z});
}
json ivec3Json(const glm::ivec3& v) {
  return json::array({v.x, v.y, v.z});
}
json percentilesJson(const simulation::Percentiles& p) {
  return {{"p50", p.p50}, {"p99", p.p99}, {"max", p.max}};
}

void printJson(const json& j) {
  std::cout << j.dump(2, ' ', false, json::error_handler_t::replace) << "\n";
}

json setupJson(const simulation::SetupTimings& t) {
  return {{"load", t.loadMs},
          {"voxelize", t.voxelizeMs},
          {"density", t.densityMs},
          {"fine_fills", t.fineFillsMs},
          {"hierarchy", t.hierarchyMs},
          {"surface", t.surfaceMs},
          {"total", t.totalMs},
          {"first_step", t.firstStepMs},
          {"surface_ready", t.surfaceReadyMs}};
}

json memoryJson(const simulation::SessionMemory& m) {
  const std::pair<const char*, std::size_t> parts[] = {
      {"bone_grid", m.boneGrid},
      {"fine_fills", m.fineFills},
      {"grid", m.grid},
      {"hierarchy", m.hierarchy},
      {"refinement", m.refinement},
      {"thermal", m.thermal},
      {"visual_grid", m.visualGrid},
      {"surface_cell_bricks", m.surface.cellBricks},
      {"surface_triangles", m.surface.triangles},
      {"surface_vertices", m.surface.vertices},
      {"surface_loops", m.surface.loops},
      {"surface_tables", m.surface.tables},
      {"surface", m.surface.total()},
      {"total", m.total()}};
  json bytes = json::object(), perVoxel = json::object();
  const double voxels = double(std::max<std::uint64_t>(m.voxels, 1));
  for (const auto& [key, value] : parts) {
    bytes[key] = value;
    perVoxel[key] = double(value) / voxels;
  }
  return {{"voxels", m.voxels}, {"bytes", bytes}, {"bytes_per_voxel", perVoxel}};
}

std::string setupLine(const simulation::SetupTimings& t, double pathMs) {
  char line[256];
  std::snprintf(line, sizeof line,
                "  set-up      %.0f ms: load %.0f, voxelize %.0f, density %.0f, fine fills %.0f, "
                "hierarchy %.0f, "
                "surface %.0f",
                t.totalMs, t.loadMs, t.voxelizeMs, t.densityMs, t.fineFillsMs, t.hierarchyMs,
                t.surfaceMs);
  std::string text = line;
  if (pathMs >= 0.0) {
    std::snprintf(line, sizeof line, ", path %.0f", pathMs);
    text += line;
  }
  std::snprintf(line, sizeof line, "; peak RSS %.0f MB", peakRssMb());
  return text + line;
}

int emptyExit(const char* command, const std::string& input, const std::string& reason,
              bool allowEmpty) {
  std::fprintf(stderr, "osteon %s: %s: empty result: %s%s\n", command, input.c_str(),
               reason.c_str(),
               allowEmpty ? " (accepted: --allow-empty)" : " (exit 1; --allow-empty accepts it)");
  return allowEmpty ? kExitOk : kExitCheckFailed;
}

}  // namespace osteon::cli
