// `osteon check`: the crack-free guarantees of one surface as numbers (docs/validation.md).
#include "commands/check.h"

#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "osteon/core/error.h"
#include "osteon/validation/crack_images.h"
#include "osteon/validation/crack_metric.h"
#include "osteon/validation/mesh_checks.h"
#include "support/output.h"

namespace osteon::cli {

using nlohmann::json;
namespace sim = osteon::simulation;
namespace val = osteon::validation;

namespace {

struct CheckReport {
  const CheckCommandOptions* options = nullptr;
  geometry::TriangleMesh mesh;
  val::MeshReport checks;
  val::CrackMetric cracks;
  std::vector<std::string> images;
  std::optional<val::Accuracy> accuracy;
  std::vector<std::string> failures;  // why the surface is not a valid bone surface; none: PASS
};

// Why a surface is not a valid bone surface, one reason each; none means PASS.
std::vector<std::string> failuresOf(const val::MeshReport& r) {
  std::vector<std::string> failures;
  // Open means a border; edges of three or more triangles are non-manifold, not open.
  if (r.topology.borderEdges > 0)
    failures.push_back("open: " + std::to_string(r.topology.borderEdges) + " border edges");
  if (!r.topology.manifold()) {
    failures.push_back("non-manifold: " + std::to_string(r.topology.nonManifoldEdges) +
                       " edges of more than two triangles, " +
                       std::to_string(r.topology.nonManifoldVertices) +
                       " vertices joining separate fans");
  }
  if (r.selfIntersections > 0) failures.push_back("self-intersecting triangles");
  if (!r.topology.consistentlyOriented()) {
    failures.push_back("inconsistently oriented: " + std::to_string(r.topology.misorientedEdges) +
                       " edges with neighbours facing opposite ways");
  } else if (r.watertight() && r.selfIntersections == 0 && !r.outwardOriented) {
    failures.push_back(
        "inside-out: the closed surface faces inward (negative volume), so its "
        "outside is drawn as a crack");
  }
  if (r.windingNumberMax > 1) {
    failures.push_back("nested shells: winding number " + std::to_string(r.windingNumberMax) +
                       " (a shell inside another that faces the same way)");
  } else if (r.windingNumberMin < 0 && r.outwardOriented) {
    failures.push_back("nested shells: winding number " + std::to_string(r.windingNumberMin) +
                       " (an inward shell that no outward one encloses)");
  }
  if (r.flat) {
    failures.push_back("encloses no volume: the closed surface is flat (a sheet with both sides)");
  }
  return failures;
}

json toJson(const CheckReport& report) {
  const val::MeshReport& r = report.checks;
  const val::CrackMetric& cracks = report.cracks;
  json j = {
      {"mesh", report.options->bone.input},
      {"verdict", report.failures.empty() ? "PASS" : "FAIL"},
      {"vertices", report.mesh.vertexCount()},
      {"triangles", report.mesh.triangleCount()},
      {"closed", r.topology.closed()},
      {"border_edges", r.topology.borderEdges},
      {"non_manifold_edges", r.topology.nonManifoldEdges},
      {"non_manifold_vertices", r.topology.nonManifoldVertices},
      {"misoriented_edges", r.topology.misorientedEdges},
      {"degenerate_faces", r.topology.degenerateTriangles},
      {"self_intersections", r.selfIntersections},
      {"self_intersections_capped", r.selfIntersectionsCapped},
      {"outward_oriented", r.outwardOriented},
      {"components", r.topology.components},
      {"euler_characteristic", r.topology.eulerCharacteristic},
      {"genus", r.genus},
      {"winding_number_min", r.windingNumberMin},
      {"winding_number_max", r.windingNumberMax},
      {"flat", r.flat},
      {"volume_mm3", r.volumeMm3},
      {"crack_percent", cracks.crackPercent()},
      {"crack_pixels", {{"red", cracks.red}, {"white", cracks.white}, {"per_side", cracks.pixels}}},
      {"crack_images", report.images},
      {"failures", report.failures}};
  if (const auto& a = report.accuracy) {
    j["reference"] = report.options->reference;
    j["hausdorff_mm"] = a->hausdorffMm;
    j["hausdorff_surface_to_reference_mm"] = a->surfaceToReferenceMm;
    j["hausdorff_reference_to_surface_mm"] = a->referenceToSurfaceMm;
    j["volume_difference_mm3"] = a->volumeDifferenceMm3;
    j["volume_difference_percent"] = a->volumeDifferencePercent;
  }
  return j;
}

void printText(const CheckReport& report) {
  const val::MeshReport& r = report.checks;
  const val::CrackMetric& cracks = report.cracks;
  std::cout << report.options->bone.input << ": " << (report.failures.empty() ? "PASS" : "FAIL")
            << " - border edges " << r.topology.borderEdges << ", non-manifold edges "
            << r.topology.nonManifoldEdges << ", vertices " << r.topology.nonManifoldVertices
            << ", self-intersections " << r.selfIntersections
            << (r.selfIntersectionsCapped ? "+" : "") << ", cracks " << cracks.crackPercent()
            << " % of " << cracks.red + cracks.white << " pixels";
  if (report.accuracy) std::cout << ", Hausdorff " << report.accuracy->hausdorffMm << " mm";
  for (const std::string& f : report.failures) std::cout << "; " << f;
  std::cout << "\n";
}

}  // namespace

int runCheck(const CheckCommandOptions& options) {
  sim::BoneSource reference = options.bone;  // the same units
  reference.input = options.reference;
  options.bone.check();
  if (options.cracks < 16 || options.cracks > 4096) {
    throw InputError("--cracks " + std::to_string(options.cracks) +
                     ": pixels per side must be 16..4096");
  }
  if (!options.images.empty()) {
    std::vector<std::string> inputs = options.bone.inputFiles();
    if (!options.reference.empty()) {
      for (const std::string& file : reference.inputFiles()) inputs.push_back(file);
    }
    val::CrackImageFolder::refuseOverwriting(options.images, inputs);
  }
  CheckReport report;
  report.options = &options;
  report.mesh = sim::loadBoneMesh(options.bone).mesh;
  const geometry::TriangleMesh referenceMesh =
      options.reference.empty() ? geometry::TriangleMesh{} : sim::loadBoneMesh(reference).mesh;
  // The six views are one set, put in place together.
  std::optional<val::CrackImageFolder> images;
  if (!options.images.empty()) images.emplace(options.images, "--images");

  report.checks = val::checkMesh(report.mesh);
  if (images) {
    report.cracks = images->write(report.mesh, options.cracks, report.images);
  } else {
    val::CrackMetricOptions co;
    co.pixels = options.cracks;
    report.cracks = val::measureCracks(report.mesh, co);
  }
  report.failures = failuresOf(report.checks);
  if (!options.reference.empty()) {
    try {
      report.accuracy = val::compareMeshes(report.mesh, referenceMesh);
    } catch (const std::invalid_argument&) {
      throw InputError(
          "--reference: " + options.bone.input + " or " + options.reference +
          " is not a polygon mesh (non-manifold), so the Hausdorff distance is undefined");
    }
  }
  printReport(report, options.json);
  return report.failures.empty() ? kExitOk : kExitCheckFailed;
}

}  // namespace osteon::cli
