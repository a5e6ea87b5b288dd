#include "commands/model.h"

#include <cstdio>

#include "osteon/core/error.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh_io.h"
#include "support/output.h"

namespace osteon::cli {

namespace geo = osteon::geometry;
using nlohmann::json;

namespace {

struct ModelReport {
  geo::HumerusModel model;
  geo::MeshTopology topology;
  double buildMs = 0.0;
  std::string out;
};

json toJson(const ModelReport& r) {
  json j = {{"vertices", r.model.mesh.vertexCount()},
            {"triangles", r.model.mesh.triangleCount()},
            {"volume_mm3", geo::signedVolumeMm3(r.model.mesh)},
            {"head_centre_mm", vec3Json(r.model.headCentreMm)},
            {"head_radius_mm", r.model.headRadiusMm},
            {"head_axis", vec3Json(r.model.headAxis)},
            {"shaft_axis", vec3Json(r.model.shaftAxis)},
            {"closed", r.topology.closed()},
            {"euler_characteristic", r.topology.eulerCharacteristic},
            {"build_ms", r.buildMs}};
  if (!r.out.empty()) j["out"] = r.out;
  return j;
}

void printText(const ModelReport& r) {
  const geo::HumerusModel& m = r.model;
  std::printf("built-in right proximal humerus: %zu vertices, %zu triangles, %.1f mm^3, %s\n",
              m.mesh.vertexCount(), m.mesh.triangleCount(), geo::signedVolumeMm3(m.mesh),
              r.topology.closed() ? "closed" : "OPEN");
  std::printf("  head centre (%.3f, %.3f, %.3f) mm, radius %.3f mm, axis (%.4f, %.4f, %.4f)\n",
              m.headCentreMm.x, m.headCentreMm.y, m.headCentreMm.z, m.headRadiusMm, m.headAxis.x,
              m.headAxis.y, m.headAxis.z);
  if (!r.out.empty()) std::printf("  wrote %s\n", r.out.c_str());
}

}  // namespace

int runModel(const ModelOptions& options) {
  ModelReport r;
  const Clock::time_point start = Clock::now();
  r.model = geo::buildHumerusModel();
  r.buildMs = msSince(start);
  r.out = options.out;
  if (!options.out.empty()) geo::writeMesh(r.model.mesh, options.out);
  r.topology = geo::analyzeTopology(r.model.mesh);
  printReport(r, options.json);
  return kExitOk;
}

}  // namespace osteon::cli
