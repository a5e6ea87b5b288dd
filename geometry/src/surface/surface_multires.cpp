// Multi-resolution surface (see extractSurface(grid, refined, ...) in surface.h): refined
// lattice inside cells with a refined corner, level-0 cells elsewhere, transition cells
// between them whose loops follow the refined segments on the shared faces.
#include <chrono>
#include <unordered_map>
#include <unordered_set>

#include <glm/geometric.hpp>

#include "osteon/core/error.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/geometry/surface/surface.h"
#include "surface_cells.h"

namespace osteon::geometry {

using namespace detail;

namespace {

constexpr double kIsoFraction = kIso / double(kFillFull);

std::uint64_t pack(const glm::ivec3& v, int offset) {
  return (std::uint64_t(v.x + offset) << 42) | (std::uint64_t(v.y + offset) << 21) |
         std::uint64_t(v.z + offset);
}

glm::ivec3 floorDiv3(const glm::ivec3& a, int b) {
  return {floorDiv(a.x, b), floorDiv(a.y, b), floorDiv(a.z, b)};
}

struct Segment {
  std::uint32_t from, to;
};

// The per-face rule of the case table (mc_table.cpp), on one square face given as corners in
// cyclic order: two crossings make one segment, four make two that cut off the outside
// corners. Each segment is oriented so that (to - from) x normal points into the inside.
void faceRule(const glm::dvec3 (&corner)[4], const bool (&inside)[4],
              const std::uint32_t (&edgeVertex)[4], const glm::dvec3& normal,
              std::vector<Segment>& out) {
  const auto mid = [&](int e) { return 0.5 * (corner[e] + corner[(e + 1) % 4]); };
  const auto add = [&](int e0, int e1, const glm::dvec3& ref, bool refInside) {
    const double side = glm::dot(glm::cross(mid(e1) - mid(e0), normal), ref - mid(e0));
    if ((side > 0.0) == refInside) {
      out.push_back({edgeVertex[e0], edgeVertex[e1]});
    } else {
      out.push_back({edgeVertex[e1], edgeVertex[e0]});
    }
  };
  int crossing[4];
  int count = 0;
  for (int e = 0; e < 4; ++e) {
    if (inside[e] != inside[(e + 1) % 4]) crossing[count++] = e;
  }
  if (count == 2) {
    int ref = 0;
    while (!inside[ref]) ++ref;
    add(crossing[0], crossing[1], corner[ref], true);
  } else if (count == 4) {
    for (int c = 0; c < 4; ++c) {
      if (inside[c]) continue;
      add((c + 3) % 4, c, corner[c], false);  // edges before and after the outside corner
    }
  }
}

struct MultiRes {
  const VoxelGrid& grid;
  int n;  // refined samples per voxel edge
  double vs;
  double h;
  glm::ivec3 dims;
  std::unordered_map<std::uint64_t, std::array<Fill, kSubVoxels>> sub;  // refined voxels
  std::unordered_set<std::uint64_t> fineCells;
  std::unordered_map<std::uint64_t, std::uint32_t> coarseVertex;
  std::unordered_map<std::uint64_t, std::uint32_t> fineVertex;
  Buffer<VertexInfo> vertices;
  Buffer<std::uint32_t> loopVertices;
  Buffer<glm::u32vec3> triangles;
  double subFull;

  MultiRes(const VoxelGrid& g, const RefinedVoxels& refined)
      : grid(g),
        n(1 << refined.depth()),
        vs(g.voxelSizeMm()),
        h(g.voxelSizeMm() / double(1 << refined.depth())),
        dims(g.dims()),
        subFull(double(kFillFull) / double(n * n * n)) {
    for (const glm::ivec3& v : refined.refinedVoxels()) {
      std::array<Fill, kSubVoxels> fill;
      std::array<Density, kSubVoxels> density;
      refined.subFill(v, fill, density);
      sub.emplace(voxelKey(v), fill);
      for (int d = 0; d < 8; ++d)
        fineCells.insert(voxelKey(v - glm::ivec3(d & 1, (d >> 1) & 1, (d >> 2) & 1)));
    }
  }

  static std::uint64_t voxelKey(const glm::ivec3& v) { return pack(v, 4); }
  std::uint64_t latticeKey(const glm::ivec3& q) const { return pack(q, 4 * n); }
  bool isFine(const glm::ivec3& cell) const { return fineCells.count(voxelKey(cell)) != 0; }

  double coarseValue(const glm::ivec3& v) const {
    return grid.inBounds(v) ? double(grid.fill(v)) / double(kFillFull) : 0.0;
  }

  // The refined-lattice sample at q (position: centre of voxel 0 + q h). Inside the refined
  // region it is the mean of the eight sub-voxels around q (an unrefined voxel counts as
  // sub-voxels of its own fill: 0 for empty, full for full). On the region's boundary faces it
  // is the trilinear interpolation of the voxel fills, so that along the level-0 edges there
  // it is linear and crosses where the level-0 cells cross.
  double value(const glm::ivec3& q) const {
    if (interior(q)) {
      const glm::ivec3 base = q + (n / 2 - 1);
      double sum = 0.0;
      for (int d = 0; d < 8; ++d) {
        const glm::ivec3 g = base + glm::ivec3(d & 1, (d >> 1) & 1, (d >> 2) & 1);
        const glm::ivec3 v = floorDiv3(g, n);
        const auto it = sub.find(voxelKey(v));
        if (it == sub.end()) {
          sum += coarseValue(v);
          continue;
        }
        const glm::ivec3 s = g - v * n;
        sum += double(it->second[std::size_t(s.x + n * (s.y + n * s.z))]) / subFull;
      }
      return sum / 8.0;
    }
    // Trilinear interpolation of the voxel fills (voxel centres at q = v n).
    const glm::ivec3 v0 = floorDiv3(q, n);
    const glm::dvec3 f = glm::dvec3(q - v0 * n) / double(n);
    double value = 0.0;
    for (int d = 0; d < 8; ++d) {
      const glm::ivec3 o(d & 1, (d >> 1) & 1, (d >> 2) & 1);
      const double w = (o.x ? f.x : 1.0 - f.x) * (o.y ? f.y : 1.0 - f.y) * (o.z ? f.z : 1.0 - f.z);
      if (w != 0.0) value += w * coarseValue(v0 + o);
    }
    return value;
  }

  // Whether every level-0 cell whose closed box holds q is a refined cell.
  bool interior(const glm::ivec3& q) const {
    glm::ivec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
      hi[a] = floorDiv(q[a], n);
      lo[a] = q[a] % n == 0 ? hi[a] - 1 : hi[a];
    }
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
          if (!isFine({x, y, z})) return false;
        }
    return true;
  }
  static bool inside(double value) { return value > kIsoFraction; }

  glm::dvec3 latticePosition(const glm::ivec3& q) const {
    return grid.voxelCentreMm({0, 0, 0}) + glm::dvec3(q) * h;
  }

  std::uint32_t coarseVertexOf(const glm::ivec3& v, int axis) {
    const std::uint64_t key = voxelKey(v) * 3 + std::uint64_t(axis);
    const auto it = coarseVertex.find(key);
    if (it != coarseVertex.end()) return it->second;
    glm::ivec3 w = v;
    ++w[axis];
    const double a = coarseValue(v), b = coarseValue(w);
    const double t = std::clamp((kIsoFraction - a) / (b - a), kEdgeMargin, 1.0 - kEdgeMargin);
    vertices.push_back({grid.voxelCentreMm(v), axis, t, vs, 0, 0, v});
    return coarseVertex[key] = std::uint32_t(vertices.size() - 1);
  }

  // A refined-lattice edge's vertex. On a level-0 edge that level-0 cells also use (a seam
  // edge), the samples along it are linear, so its one crossing is the level-0 crossing: the
  // same vertex.
  std::uint32_t fineVertexOf(const glm::ivec3& q, int axis) {
    const int u = (axis + 1) % 3;
    const int w = (axis + 2) % 3;
    if (q[u] % n == 0 && q[w] % n == 0) {
      glm::ivec3 v = floorDiv3(q, n);
      bool seam = false;
      for (int d = 0; d < 4 && !seam; ++d) {
        glm::ivec3 cell = v;
        cell[u] -= d & 1;
        cell[w] -= (d >> 1) & 1;
        seam = !isFine(cell);
      }
      if (seam) return coarseVertexOf(v, axis);
    }
    const std::uint64_t key = latticeKey(q) * 3 + std::uint64_t(axis);
    const auto it = fineVertex.find(key);
    if (it != fineVertex.end()) return it->second;
    glm::ivec3 q1 = q;
    ++q1[axis];
    const double a = value(q), b = value(q1);
    const double t = std::clamp((kIsoFraction - a) / (b - a), kEdgeMargin, 1.0 - kEdgeMargin);
    vertices.push_back({latticePosition(q), axis, t, h, 0, 0, q});
    return fineVertex[key] = std::uint32_t(vertices.size() - 1);
  }

  void emitLoop(const std::uint32_t* ids, int count) {
    if (count == 3) {
      triangles.push_back({ids[0], ids[1], ids[2]});
      return;
    }
    if (count == 4) {
      triangles.push_back({ids[0], ids[1], ids[2]});
      triangles.push_back({ids[0], ids[2], ids[3]});
      return;
    }
    const auto first = std::uint32_t(loopVertices.size());
    loopVertices.insert(loopVertices.end(), ids, ids + count);
    vertices.push_back({glm::dvec3(0.0), 3, 0.0, 0.0, first, std::uint32_t(count), glm::ivec3(0)});
    const auto centre = std::uint32_t(vertices.size() - 1);
    for (int i = 0; i < count; ++i) triangles.push_back({centre, ids[i], ids[(i + 1) % count]});
  }

  // One refined cell (corner q0 on the refined lattice), through the case table.
  void fineCell(const glm::ivec3& q0) {
    int config = 0;
    for (int c = 0; c < 8; ++c) {
      if (inside(value(q0 + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1)))) config |= 1 << c;
    }
    if (config == 0 || config == 255) return;
    emitCase(config, [&](int e) { return fineVertexOf(edgeStart(q0, e), e / 4); });
  }

  // The case table's loops for one cell, each cube edge's vertex from vertexOf(edge).
  template <typename VertexOf>
  void emitCase(int config, VertexOf&& vertexOf) {
    const McCase& mc = mcTable()[std::size_t(config)];
    std::uint32_t ids[13];
    for (int loop = 0; loop < mc.loopCount; ++loop) {
      int count = 0;
      for (int k = mc.loopBegin[std::size_t(loop)]; k < mc.loopBegin[std::size_t(loop) + 1]; ++k) {
        ids[count++] = vertexOf(int(mc.edges[std::size_t(k)]));
      }
      emitLoop(ids, count);
    }
  }

  // A level-0 cell with no refined corner: the case table, unless a face borders refined
  // cells; then its loops are chained from the segments of each face, refined on those faces.
  void coarseCell(const glm::ivec3& c) {
    bool transition = false;
    for (int f = 0; f < 6 && !transition; ++f) {
      glm::ivec3 nb = c;
      nb[f / 2] += (f % 2) ? 1 : -1;
      transition = isFine(nb);
    }
    double corner[8];
    int config = 0;
    for (int k = 0; k < 8; ++k) {
      corner[k] = coarseValue(c + glm::ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
      if (inside(corner[k])) config |= 1 << k;
    }
    if (config == 0 || config == 255) return;
    if (!transition) {
      emitCase(config, [&](int e) { return coarseVertexOf(edgeStart(c, e), e / 4); });
      return;
    }
    std::vector<Segment> segments;
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3;
      const int w = (axis + 2) % 3;
      for (int side = 0; side < 2; ++side) {
        glm::dvec3 normal(0.0);
        normal[axis] = side ? 1.0 : -1.0;
        glm::ivec3 nb = c;
        nb[axis] += side ? 1 : -1;
        // Face corners in cyclic order (u, v offsets (0,0), (1,0), (1,1), (0,1)).
        const int du[4] = {0, 1, 1, 0};
        const int dw[4] = {0, 0, 1, 1};
        if (!isFine(nb)) {
          glm::dvec3 pos[4];
          bool in[4];
          std::uint32_t ev[4];
          glm::ivec3 vox[4];
          for (int k = 0; k < 4; ++k) {
            vox[k] = c;
            vox[k][axis] += side;
            vox[k][u] += du[k];
            vox[k][w] += dw[k];
            pos[k] = glm::dvec3(vox[k]);
            in[k] = inside(coarseValue(vox[k]));
          }
          for (int k = 0; k < 4; ++k) {
            const glm::ivec3 a = vox[k], b = vox[(k + 1) % 4];
            const int edgeAxis = a[u] != b[u] ? u : w;
            ev[k] = in[k] != in[(k + 1) % 4] ? coarseVertexOf(glm::min(a, b), edgeAxis) : kNoVertex;
          }
          faceRule(pos, in, ev, normal, segments);
          continue;
        }
        // The face as n x n refined faces.
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) {
            glm::dvec3 pos[4];
            bool in[4];
            std::uint32_t ev[4];
            glm::ivec3 q[4];
            for (int k = 0; k < 4; ++k) {
              q[k] = c * n;
              q[k][axis] += side * n;
              q[k][u] += i + du[k];
              q[k][w] += j + dw[k];
              pos[k] = glm::dvec3(q[k]);
              in[k] = inside(value(q[k]));
            }
            for (int k = 0; k < 4; ++k) {
              const glm::ivec3 a = q[k], b = q[(k + 1) % 4];
              const int edgeAxis = a[u] != b[u] ? u : w;
              ev[k] = in[k] != in[(k + 1) % 4] ? fineVertexOf(glm::min(a, b), edgeAxis) : kNoVertex;
            }
            faceRule(pos, in, ev, normal, segments);
          }
      }
    }
    // Chain the segments into loops (every vertex leaves once and arrives once).
    std::unordered_map<std::uint32_t, std::uint32_t> next;
    for (const Segment& s : segments) {
      if (!next.emplace(s.from, s.to).second) {
        throw std::logic_error("multi-resolution surface: a transition loop branches");
      }
    }
    std::unordered_set<std::uint32_t> used;
    std::vector<std::uint32_t> loop;
    for (const Segment& s : segments) {
      if (used.count(s.from)) continue;
      loop.clear();
      for (std::uint32_t v = s.from; !used.count(v);) {
        used.insert(v);
        loop.push_back(v);
        const auto it = next.find(v);
        if (it == next.end()) throw std::logic_error("multi-resolution surface: an open loop");
        v = it->second;
      }
      emitLoop(loop.data(), int(loop.size()));
    }
  }
};

}  // namespace

SurfaceMesh extractSurface(const VoxelGrid& grid, const RefinedVoxels& refined,
                           const SurfaceOptions& options, SurfaceTimings* timings) {
  validateSurfaceOptions(options);
  if (refined.depth() == 0 || refined.refinedCount() == 0) {
    SurfaceOptions crackFree = options;
    crackFree.method = SurfaceMethod::CrackFree;
    return extractSurface(grid, crackFree, timings);
  }
  SurfaceTimings local;
  const auto start = Clock::now();
  MultiRes m(grid, refined);
  const glm::ivec3 cellBricks = grid.brickDims() + 1;
  for (int bz = -1; bz < cellBricks.z - 1; ++bz)
    for (int by = -1; by < cellBricks.y - 1; ++by)
      for (int bx = -1; bx < cellBricks.x - 1; ++bx) {
        const glm::ivec3 cb(bx, by, bz);
        if (!cellBrickActive(grid, cb)) continue;
        glm::ivec3 lo, hi;
        cellRange(grid, cb, lo, hi);
        for (int z = lo.z; z < hi.z; ++z)
          for (int y = lo.y; y < hi.y; ++y)
            for (int x = lo.x; x < hi.x; ++x) {
              const glm::ivec3 c(x, y, z);
              if (!m.isFine(c)) m.coarseCell(c);
            }
      }
  // Refined cells, in a fixed order.
  std::vector<std::uint64_t> fine(m.fineCells.begin(), m.fineCells.end());
  std::sort(fine.begin(), fine.end());
  for (const std::uint64_t key : fine) {
    const glm::ivec3 c(int((key >> 42) & 0x1fffff) - 4, int((key >> 21) & 0x1fffff) - 4,
                       int(key & 0x1fffff) - 4);
    for (int k = 0; k < m.n; ++k)
      for (int j = 0; j < m.n; ++j)
        for (int i = 0; i < m.n; ++i) m.fineCell(c * m.n + glm::ivec3(i, j, k));
  }
  local.extractMs = msSince(start);
  SurfaceMesh mesh;
  finishSurface(m.vertices, m.loopVertices, m.triangles,
                {options.smoothIterations, options.lambda, options.taubin, options.mu,
                 options.computeNormals},
                mesh.positionsMm, mesh.normals, local.otherMs, local.smoothMs, local.normalsMs);
  mesh.triangles = std::move(m.triangles);
  local.totalMs = msSince(start);
  if (timings) *timings = local;
  return mesh;
}

}  // namespace osteon::geometry
