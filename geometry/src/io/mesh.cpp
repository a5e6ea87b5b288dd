#include "osteon/geometry/io/mesh.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <utility>

#include <glm/geometric.hpp>

namespace osteon::geometry {

Aabb bounds(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) throw std::invalid_argument("bounds: mesh has no triangles");
  Aabb box;
  box.minMm = box.maxMm = mesh.positionsMm[mesh.triangles.front().x];
  for (const glm::u32vec3& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      const glm::dvec3& p = mesh.positionsMm[t[c]];
      box.minMm = glm::min(box.minMm, p);
      box.maxMm = glm::max(box.maxMm, p);
    }
  }
  return box;
}

double signedVolumeMm3(const TriangleMesh& mesh) {
  // Sum of signed tetrahedra against a point near the mesh (its first vertex): far less
  // cancellation than against the origin when a mesh sits far from it.
  if (mesh.triangles.empty()) return 0.0;
  const glm::dvec3 ref = mesh.positionsMm[mesh.triangles.front().x];
  double sixV = 0.0;
  for (const glm::u32vec3& t : mesh.triangles) {
    const glm::dvec3 a = mesh.positionsMm[t.x] - ref;
    const glm::dvec3 b = mesh.positionsMm[t.y] - ref;
    const glm::dvec3 c = mesh.positionsMm[t.z] - ref;
    sixV += glm::dot(a, glm::cross(b, c));
  }
  return sixV / 6.0;
}

double surfaceAreaMm2(const TriangleMesh& mesh) {
  double twiceArea = 0.0;
  for (const glm::u32vec3& t : mesh.triangles) {
    const glm::dvec3& a = mesh.positionsMm[t.x];
    twiceArea += glm::length(glm::cross(mesh.positionsMm[t.y] - a, mesh.positionsMm[t.z] - a));
  }
  return 0.5 * twiceArea;
}

void scaleInPlace(TriangleMesh& mesh, double factor) {
  for (glm::dvec3& p : mesh.positionsMm) p *= factor;
}

namespace {

// Union-find over vertex indices, for connected components.
struct DisjointSets {
  std::vector<std::uint32_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

// Pinched vertices: the triangles around a vertex must form one fan, i.e. the edges opposite
// the vertex (its link) must be connected.
std::size_t countPinchedVertices(const TriangleMesh& mesh) {
  std::size_t pinched = 0;
  const std::size_t nv = mesh.positionsMm.size();
  std::vector<std::uint32_t> start(nv + 1, 0);
  for (const glm::u32vec3& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) ++start[t[c] + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> link(2 * std::size_t(start[nv]));
  std::vector<std::uint32_t> at(start.begin(), start.end() - 1);
  for (const glm::u32vec3& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      const std::size_t slot = at[t[c]]++;
      link[2 * slot] = t[(c + 1) % 3];
      link[2 * slot + 1] = t[(c + 2) % 3];
    }
  }
  std::vector<std::uint32_t> local;  // link vertices, union-find over their positions
  std::vector<std::uint32_t> parent;
  for (std::size_t v = 0; v < nv; ++v) {
    const std::uint32_t b = start[v];
    const std::uint32_t e = start[v + 1];
    if (e - b < 2) continue;
    local.assign(link.begin() + 2 * b, link.begin() + 2 * e);
    std::sort(local.begin(), local.end());
    local.erase(std::unique(local.begin(), local.end()), local.end());
    parent.resize(local.size());
    std::iota(parent.begin(), parent.end(), 0u);
    const auto find = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    std::size_t groups = local.size();
    for (std::uint32_t k = b; k < e; ++k) {
      const auto i =
          std::uint32_t(std::lower_bound(local.begin(), local.end(), link[2 * k]) - local.begin());
      const auto j = std::uint32_t(std::lower_bound(local.begin(), local.end(), link[2 * k + 1]) -
                                   local.begin());
      const std::uint32_t ri = find(i), rj = find(j);
      if (ri != rj) {
        parent[ri] = rj;
        --groups;
      }
    }
    if (groups > 1) ++pinched;
  }
  return pinched;
}

}  // namespace

MeshTopology analyzeTopology(const TriangleMesh& mesh) {
  MeshTopology topo;
  // Directed half-edges, sorted by their undirected key, so each edge's uses sit together.
  struct HalfEdge {
    std::uint64_t key;  // min << 32 | max
    bool forward;       // traversed min -> max
  };
  std::vector<HalfEdge> halfEdges;
  halfEdges.reserve(mesh.triangles.size() * 3);
  std::vector<char> referenced(mesh.positionsMm.size(), 0);
  DisjointSets sets(mesh.positionsMm.size());

  for (const glm::u32vec3& t : mesh.triangles) {
    const bool repeated = t.x == t.y || t.y == t.z || t.x == t.z;
    if (repeated) {
      ++topo.degenerateTriangles;
    } else {
      const glm::dvec3& a = mesh.positionsMm[t.x];
      const glm::dvec3 n = glm::cross(mesh.positionsMm[t.y] - a, mesh.positionsMm[t.z] - a);
      if (glm::dot(n, n) == 0.0) ++topo.degenerateTriangles;
    }
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t u = t[c];
      const std::uint32_t v = t[(c + 1) % 3];
      referenced[u] = 1;
      sets.unite(u, v);
      if (u == v) continue;
      const std::uint32_t lo = std::min(u, v);
      const std::uint32_t hi = std::max(u, v);
      halfEdges.push_back({(std::uint64_t(lo) << 32) | hi, u < v});
    }
  }
  std::sort(halfEdges.begin(), halfEdges.end(),
            [](const HalfEdge& a, const HalfEdge& b) { return a.key < b.key; });
  for (std::size_t i = 0; i < halfEdges.size();) {
    std::size_t j = i;
    std::size_t forward = 0;
    while (j < halfEdges.size() && halfEdges[j].key == halfEdges[i].key) {
      forward += halfEdges[j].forward ? 1u : 0u;
      ++j;
    }
    const std::size_t uses = j - i;
    ++topo.edges;
    if (uses == 1) ++topo.borderEdges;
    if (uses > 2) ++topo.nonManifoldEdges;
    if (uses == 2 && forward != 1) ++topo.misorientedEdges;
    i = j;
  }

  topo.nonManifoldVertices = countPinchedVertices(mesh);

  long long vertices = 0;
  for (std::size_t v = 0; v < referenced.size(); ++v) {
    if (!referenced[v]) continue;
    ++vertices;
    if (sets.find(static_cast<std::uint32_t>(v)) == v) ++topo.components;
  }
  topo.eulerCharacteristic =
      vertices - static_cast<long long>(topo.edges) + static_cast<long long>(mesh.triangles.size());
  return topo;
}

}  // namespace osteon::geometry
