#include "marching_tetrahedra.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

namespace osteon::geometry::detail {

namespace {

// Kuhn split of the unit cube: every tetrahedron walks from corner (0,0,0) to (1,1,1) along
// the three axes in one of the six orders, so all of them share the main diagonal.
constexpr std::array<std::array<int, 3>, 6> kAxisOrders = {
    {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};

// Collects the mesh: grid-vertex positions and values, and one mesh vertex per crossed edge.
class TetPolygoniser {
 public:
  TetPolygoniser(const std::vector<glm::dvec3>& gridPositions, const std::vector<double>& values,
                 TriangleMesh& mesh)
      : positions_(gridPositions), values_(values), mesh_(mesh) {}

  void addTetrahedron(const std::array<std::uint32_t, 4>& ids) {
    std::array<std::uint32_t, 4> inside{};
    std::array<std::uint32_t, 4> outside{};
    std::size_t nIn = 0;
    std::size_t nOut = 0;
    for (std::uint32_t id : ids) {
      if (values_[id] < 0.0) {
        inside[nIn++] = id;
      } else {
        outside[nOut++] = id;
      }
    }
    if (nIn == 0 || nOut == 0) return;
    if (nIn == 1) {
      addTriangle(edgeVertex(inside[0], outside[0]), edgeVertex(inside[0], outside[1]),
                  edgeVertex(inside[0], outside[2]),
                  positions_[outside[0]] - positions_[inside[0]]);
    } else if (nOut == 1) {
      addTriangle(edgeVertex(outside[0], inside[0]), edgeVertex(outside[0], inside[1]),
                  edgeVertex(outside[0], inside[2]),
                  positions_[outside[0]] - positions_[inside[0]]);
    } else {
      // Two in, two out: the crossed edges form a quad in cyclic order a-c, a-d, b-d, b-c.
      const std::uint32_t q[4] = {
          edgeVertex(inside[0], outside[0]), edgeVertex(inside[0], outside[1]),
          edgeVertex(inside[1], outside[1]), edgeVertex(inside[1], outside[0])};
      const glm::dvec3 outward = positions_[outside[0]] + positions_[outside[1]] -
                                 positions_[inside[0]] - positions_[inside[1]];
      // Split along the shorter diagonal: better shaped triangles.
      const auto& p = mesh_.positionsMm;
      const double d02 = glm::length(p[q[2]] - p[q[0]]);
      const double d13 = glm::length(p[q[3]] - p[q[1]]);
      if (d02 <= d13) {
        addTriangle(q[0], q[1], q[2], outward);
        addTriangle(q[0], q[2], q[3], outward);
      } else {
        addTriangle(q[1], q[2], q[3], outward);
        addTriangle(q[1], q[3], q[0], outward);
      }
    }
  }

 private:
  // The zero crossing of the linear interpolant on grid edge (a, b), made once per edge.
  std::uint32_t edgeVertex(std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    const std::uint64_t key = (std::uint64_t(a) << 32) | b;
    const auto [it, added] =
        edgeVertices_.try_emplace(key, static_cast<std::uint32_t>(mesh_.positionsMm.size()));
    if (added) {
      const double t = values_[a] / (values_[a] - values_[b]);
      mesh_.positionsMm.push_back(positions_[a] + t * (positions_[b] - positions_[a]));
    }
    return it->second;
  }

  // Orients the triangle so its normal points along `outward` (from inside to outside
  // grid vertices of the tetrahedron: the interpolant's gradient direction there).
  void addTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, const glm::dvec3& outward) {
    const auto& p = mesh_.positionsMm;
    const glm::dvec3 n = glm::cross(p[b] - p[a], p[c] - p[a]);
    if (glm::dot(n, outward) < 0.0) std::swap(b, c);
    mesh_.triangles.emplace_back(a, b, c);
  }

  const std::vector<glm::dvec3>& positions_;
  const std::vector<double>& values_;
  TriangleMesh& mesh_;
  std::unordered_map<std::uint64_t, std::uint32_t> edgeVertices_;  // lookup only, never iterated
};

// Sorted unique neighbours of every vertex (compressed rows).
struct Neighbours {
  std::vector<std::uint32_t> start;
  std::vector<std::uint32_t> ids;
};

Neighbours vertexNeighbours(const TriangleMesh& mesh) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  pairs.reserve(mesh.triangles.size() * 6);
  for (const glm::u32vec3& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      pairs.emplace_back(t[c], t[(c + 1) % 3]);
      pairs.emplace_back(t[(c + 1) % 3], t[c]);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  Neighbours nb;
  nb.start.assign(mesh.positionsMm.size() + 1, 0);
  for (const auto& pr : pairs) ++nb.start[pr.first + 1];
  for (std::size_t i = 1; i < nb.start.size(); ++i) nb.start[i] += nb.start[i - 1];
  nb.ids.reserve(pairs.size());
  for (const auto& pr : pairs) nb.ids.push_back(pr.second);
  return nb;
}

}  // namespace

glm::dvec3 implicitGradient(const ImplicitFunction& f, const glm::dvec3& pMm, double stepMm) {
  const glm::dvec3 dx(stepMm, 0.0, 0.0);
  const glm::dvec3 dy(0.0, stepMm, 0.0);
  const glm::dvec3 dz(0.0, 0.0, stepMm);
  return glm::dvec3(f(pMm + dx) - f(pMm - dx), f(pMm + dy) - f(pMm - dy),
                    f(pMm + dz) - f(pMm - dz)) /
         (2.0 * stepMm);
}

TriangleMesh marchingTetrahedra(const ImplicitFunction& f, const Aabb& box, double spacingMm) {
  const glm::dvec3 origin = box.minMm - 2.0 * spacingMm;
  const glm::dvec3 extent = box.extentMm() + 4.0 * spacingMm;
  const int nx = static_cast<int>(std::ceil(extent.x / spacingMm)) + 1;  // grid vertices
  const int ny = static_cast<int>(std::ceil(extent.y / spacingMm)) + 1;
  const int nz = static_cast<int>(std::ceil(extent.z / spacingMm)) + 1;
  if (double(nx) * ny * nz >= 4294967296.0) {
    throw std::length_error("marchingTetrahedra: grid too large for 32-bit ids");
  }
  const auto id = [&](int i, int j, int k) {
    return static_cast<std::uint32_t>(i + nx * (j + ny * k));
  };

  // Values exactly (or nearly) zero would put mesh vertices on grid vertices and make
  // zero-area triangles; nudging them outward moves the surface by a negligible amount.
  const double tiny = 1e-6 * spacingMm;
  std::vector<glm::dvec3> positions(std::size_t(nx) * std::size_t(ny) * std::size_t(nz));
  std::vector<double> values(positions.size());
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const std::uint32_t v = id(i, j, k);
        positions[v] = origin + spacingMm * glm::dvec3(i, j, k);
        const bool border = i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
        const double value = f(positions[v]);
        // The outer layer counts as outside whatever f says, so the result is always closed.
        values[v] = border ? std::max(value, spacingMm) : (std::abs(value) < tiny ? tiny : value);
      }
    }
  }

  TriangleMesh mesh;
  TetPolygoniser polygoniser(positions, values, mesh);
  for (int k = 0; k + 1 < nz; ++k) {
    for (int j = 0; j + 1 < ny; ++j) {
      for (int i = 0; i + 1 < nx; ++i) {
        std::array<std::uint32_t, 8> corner{};  // bit 0: +x, bit 1: +y, bit 2: +z
        bool anyIn = false;
        bool anyOut = false;
        for (int c = 0; c < 8; ++c) {
          const std::uint32_t at = id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          corner[std::size_t(c)] = at;
          (values[at] < 0.0 ? anyIn : anyOut) = true;
        }
        if (!anyIn || !anyOut) continue;
        for (const auto& order : kAxisOrders) {
          const std::size_t b1 = std::size_t(1) << order[0];
          const std::size_t b2 = b1 | (std::size_t(1) << order[1]);
          polygoniser.addTetrahedron({corner[0], corner[b1], corner[b2], corner[7]});
        }
      }
    }
  }
  return mesh;
}

void relaxOntoZeroSet(TriangleMesh& mesh, const ImplicitFunction& f, double spacingMm,
                      int iterations) {
  const Neighbours nb = vertexNeighbours(mesh);
  const double stepMm = 1e-3 * spacingMm;
  constexpr double kRate = 0.6;  // fraction of the way to the neighbour average
  constexpr int kNewtonSteps = 2;
  std::vector<glm::dvec3> next(mesh.positionsMm.size());
  for (int iteration = 0; iteration < iterations; ++iteration) {
    const std::vector<glm::dvec3>& p = mesh.positionsMm;
    for (std::size_t v = 0; v < p.size(); ++v) {
      const std::uint32_t first = nb.start[v];
      const std::uint32_t last = nb.start[v + 1];
      if (first == last) {
        next[v] = p[v];
        continue;
      }
      glm::dvec3 average(0.0);
      for (std::uint32_t e = first; e < last; ++e) average += p[nb.ids[e]];
      average /= double(last - first);
      glm::dvec3 move = kRate * (average - p[v]);
      const glm::dvec3 g = implicitGradient(f, p[v], stepMm);
      const double g2 = glm::dot(g, g);
      if (g2 > 0.0) move -= (glm::dot(move, g) / g2) * g;  // keep it in the tangent plane
      glm::dvec3 q = p[v] + move;
      for (int s = 0; s < kNewtonSteps; ++s) {
        const glm::dvec3 gq = implicitGradient(f, q, stepMm);
        const double gq2 = glm::dot(gq, gq);
        if (!(gq2 > 0.0)) break;
        q -= (f(q) / gq2) * gq;
      }
      next[v] = q;
    }
    mesh.positionsMm.swap(next);
  }
}

}  // namespace osteon::geometry::detail
