// Checks of extracted surfaces shared by the surface tests: everything wrong with a surface
// that should be a closed, oriented 2-manifold, over every smoothing variant.
#pragma once

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/surface_grids.h"

namespace osteon::geometry::surface_test {

using namespace osteon::test;

// Everything wrong with a surface that should be a closed, oriented 2-manifold enclosing a
// positive volume, in one line ("" when nothing). Self-intersection is checked exactly, on
// the same grids, in tests/validation/surface_exact_test.cpp (CGAL stays out of geometry).
inline std::string surfaceProblems(const SurfaceMesh& s) {
  std::ostringstream out;
  for (const glm::u32vec3& t : s.triangles) {
    if (t.x >= s.vertexCount() || t.y >= s.vertexCount() || t.z >= s.vertexCount()) {
      out << " index out of range;";
      return out.str();
    }
  }
  for (const glm::dvec3& p : s.positionsMm) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      out << " non-finite position;";
      break;
    }
  }
  const TriangleMesh mesh = s.toTriangleMesh();
  const MeshTopology topo = analyzeTopology(mesh);
  if (topo.borderEdges) out << " borderEdges " << topo.borderEdges << ";";
  if (topo.nonManifoldEdges) out << " nonManifoldEdges " << topo.nonManifoldEdges << ";";
  if (topo.nonManifoldVertices) out << " nonManifoldVertices " << topo.nonManifoldVertices << ";";
  if (topo.misorientedEdges) out << " misorientedEdges " << topo.misorientedEdges << ";";
  if (topo.degenerateTriangles) out << " degenerateTriangles " << topo.degenerateTriangles << ";";
  if (s.triangleCount() > 0) {
    const double volume = signedVolumeMm3(mesh);
    if (!(volume > 0.0)) out << " signed volume " << volume << ";";
  }
  return out.str();
}

// Runs every smoothing variant on the grid and returns the failures, one line each.
inline std::vector<std::string> watertightFailures(const VoxelGrid& grid, const std::string& what) {
  std::vector<std::string> failures;
  for (const auto& [name, options] : smoothingVariants()) {
    const SurfaceMesh s = extractSurface(grid, options);
    const std::string problems = surfaceProblems(s);
    if (!problems.empty()) failures.push_back(what + ", " + name + ":" + problems);
  }
  return failures;
}

inline std::string joinFirst(const std::vector<std::string>& lines, std::size_t n = 12) {
  std::string out;
  for (std::size_t i = 0; i < std::min(n, lines.size()); ++i) out += "\n  " + lines[i];
  if (lines.size() > n) out += "\n  ... " + std::to_string(lines.size() - n) + " more";
  return out;
}

inline MeshTopology topologyOf(const SurfaceMesh& s) {
  return analyzeTopology(s.toTriangleMesh());
}

inline VoxelGrid voxelizeAt(const TriangleMesh& mesh, double voxelSizeMm) {
  VoxelizeOptions options;
  options.voxelSizeMm = voxelSizeMm;
  return voxelize(mesh, options);
}

}  // namespace osteon::geometry::surface_test
