// The triangle soup every stage exchanges: positions in millimetres, triangles as index
// triples, outward counter-clockwise by convention. No topology is imposed, so meshes with
// holes, fins or self-intersections load without losing a triangle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace osteon::geometry {

struct TriangleMesh {
  std::vector<glm::dvec3> positionsMm;  // vertex positions (nv x 3), millimetres
  std::vector<glm::u32vec3> triangles;  // vertex indices (nt x 3), outward CCW

  std::size_t vertexCount() const { return positionsMm.size(); }
  std::size_t triangleCount() const { return triangles.size(); }
};

// Calls f(a, b, c) with the corners (mm) of every triangle whose indices lie in range: a soup
// from a file may reference vertices it lacks, and every walk skips those the same way.
template <typename F>
void forEachTriangle(const TriangleMesh& mesh, F&& f) {
  const std::size_t nv = mesh.positionsMm.size();
  for (const glm::u32vec3& t : mesh.triangles) {
    if (t.x >= nv || t.y >= nv || t.z >= nv) continue;
    f(mesh.positionsMm[t.x], mesh.positionsMm[t.y], mesh.positionsMm[t.z]);
  }
}

struct Aabb {
  glm::dvec3 minMm{0.0};
  glm::dvec3 maxMm{0.0};
  glm::dvec3 extentMm() const { return maxMm - minMm; }
};

// Bounds of the vertices that triangles reference. Requires at least one triangle.
Aabb bounds(const TriangleMesh& mesh);

// Signed enclosed volume by the divergence theorem (positive for outward orientation).
double signedVolumeMm3(const TriangleMesh& mesh);

double surfaceAreaMm2(const TriangleMesh& mesh);

// Multiplies every position by factor (unit conversion to millimetres).
void scaleInPlace(TriangleMesh& mesh, double factor);

// Combinatorial facts about the soup, counted on undirected edges keyed by vertex index.
struct MeshTopology {
  std::size_t edges = 0;
  std::size_t borderEdges = 0;          // edges with one incident triangle
  std::size_t nonManifoldEdges = 0;     // edges with more than two incident triangles
  std::size_t misorientedEdges = 0;     // two-triangle edges traversed the same way by both
  std::size_t nonManifoldVertices = 0;  // triangles around the vertex form several fans
  std::size_t degenerateTriangles = 0;  // repeated index or zero area
  std::size_t components = 0;           // connected through shared vertices
  long long eulerCharacteristic = 0;    // V - E + F over referenced vertices
  bool closed() const { return borderEdges == 0 && nonManifoldEdges == 0; }
  bool manifold() const { return nonManifoldEdges == 0 && nonManifoldVertices == 0; }
  bool consistentlyOriented() const { return misorientedEdges == 0; }
};

MeshTopology analyzeTopology(const TriangleMesh& mesh);

}  // namespace osteon::geometry
