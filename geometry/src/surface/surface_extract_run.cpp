#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>
#include <type_traits>
#include <utility>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "osteon/core/constants.h"
#include "osteon/core/error.h"
#include "osteon/core/option_error.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/surface/surface.h"
#include "surface_builder.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__linux__)
#include <sched.h>
#endif
namespace osteon::geometry {
namespace detail {

// The naive baseline: every cube makes its own vertex on each of its crossed edges.
void Builder::writeTrianglesNaive(std::size_t s, Buffer<VertexInfo>& vertices,
                                  Buffer<glm::dvec3>& positions,
                                  Buffer<std::uint32_t>& loopVertices,
                                  Buffer<glm::u32vec3>& triangles) {
  const auto& table = mcTable();
  const glm::ivec3 cb = active[s];
  const BrickOut& o = out[ring[s]];
  std::uint32_t nextTri = triOffset[s];
  std::uint32_t nextExtra = extraOffset[s];
  std::uint32_t nextEntry = loopOffset[s];
  forEachSurfaceRow(o, [&](int row, int ly, int lz) {
    const std::uint64_t configs = o.configs[std::size_t(row)];
    for (std::uint32_t bits = o.mixed[std::size_t(row)]; bits != 0; bits &= bits - 1) {
      const glm::ivec3 l(__builtin_ctz(bits), ly, lz);
      const McCase& mc = table[std::size_t((configs >> (8 * l.x)) & 0xffu)];
      std::uint32_t ids[13];
      for (int loop = 0; loop < mc.loopCount; ++loop) {
        int count = 0;
        for (int k = mc.loopBegin[std::size_t(loop)]; k < mc.loopBegin[std::size_t(loop) + 1];
             ++k) {
          const int e = mc.edges[std::size_t(k)];
          const glm::ivec3 start = edgeStart(l, e);
          const int axis = e / 4;
          const VertexInfo v = edgeVertexInfo(
              grid, cb * kBrickEdge + start, axis, o.source.at(start.x, start.y, start.z),
              o.source.at(start.x + (axis == 0), start.y + (axis == 1), start.z + (axis == 2)));
          if (direct) {
            positions[nextExtra] = positionOf(v);
          } else {
            vertices[nextExtra] = v;
          }
          ids[count++] = nextExtra++;
        }
        if (count == 3) {
          triangles[nextTri++] = {ids[0], ids[1], ids[2]};
        } else if (count == 4) {
          triangles[nextTri++] = {ids[0], ids[1], ids[2]};
          triangles[nextTri++] = {ids[0], ids[2], ids[3]};
        } else {
          // Longer loops fan from their centre, as in the crack-free method.
          if (direct) {
            glm::dvec3 sum(0.0);
            for (int i = 0; i < count; ++i) sum += positions[ids[i]];
            positions[nextExtra] = sum / double(count);
          } else {
            std::copy(ids, ids + count, loopVertices.begin() + nextEntry);
            vertices[nextExtra] = {glm::dvec3(0.0), 3, 0.0, 0.0, nextEntry, std::uint32_t(count),
                                   glm::ivec3(0)};
            nextEntry += std::uint32_t(count);
          }
          const std::uint32_t centre = nextExtra++;
          for (int i = 0; i < count; ++i)
            triangles[nextTri++] = {centre, ids[i], ids[(i + 1) % count]};
        }
      }
    }
  });
}

namespace {

// Whether this thread may use only itself: a process pinned to one CPU (asked of the kernel
// first: asking TBB would start its runtime, which reads the machine's topology, 0.14 ms of a
// fresh process's first extraction that a serial one never uses), a global_control of one
// thread, or an arena of one.
bool oneThreadAllowed() {
#if defined(__linux__)
  cpu_set_t cpus;
  CPU_ZERO(&cpus);
  if (sched_getaffinity(0, sizeof cpus, &cpus) == 0 && CPU_COUNT(&cpus) <= 1) return true;
#endif
  return std::min<std::size_t>(
             tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism),
             std::size_t(tbb::this_task_arena::max_concurrency())) <= 1;
}

}  // namespace

// The run's bookkeeping reset and its outputs' room reserved; returns the cell bricks of a slab.
std::size_t Builder::prepare(Buffer<VertexInfo>& vertices, Buffer<glm::dvec3>& positions,
                             Buffer<std::uint32_t>& loopVertices, Buffer<glm::u32vec3>& triangles) {
  slotOfBrick.assign(
      std::size_t(cellBricks.x) * std::size_t(cellBricks.y) * std::size_t(cellBricks.z), -1);
  vertexOffset.assign(1, 0);
  centreOffset.assign(1, 0);
  triOffset.assign(1, 0);
  loopOffset.assign(1, 0);
  extraOffset.clear();
  // Per brick state for two slabs at a time (pass 1 on one while the brick pass reads the
  // slab below and its own), a half for each: the same few hundred KiB, in cache, all along.
  const std::size_t slabBricks = std::size_t(cellBricks.x) * std::size_t(cellBricks.y);
  out.resize(2 * slabBricks);
  index.resize(2 * slabBricks);
  ring.clear();
  // Outputs grow slab by slab. Room for as much as this thread's last extraction made spares
  // repeated extractions of a changing grid any regrowth; a first one goes by the grid's
  // stored bricks: a smooth surface makes 50-90 vertices per stored brick (the humerus at
  // 0.25-1.2 mm, a voxelized sphere) and about two triangles per vertex, so 96 leave room for
  // it without regrowing (a fresh allocation and a copy); noise makes ~1,000 and regrows.
  const std::size_t vertexGuess = 96 * grid.allocatedBrickCount();
  const std::array<std::size_t, 4> room = {
      std::max(lastTotals[0], vertexGuess), std::max(lastTotals[1], 2 * vertexGuess),
      std::max(lastTotals[2], vertexGuess / 2), std::max(lastTotals[3], vertexGuess / 8)};
  // An output of a quarter MiB or more takes a large block (one 2 MiB huge page, 0.2 ms to
  // fault in, where its 4 KiB pages would take 2.2 us each: 0.35 ms for a 64^3 sphere's).
  const auto reserveOutput = [](auto& buffer, std::size_t count) {
    using T = typename std::decay_t<decltype(buffer)>::value_type;
    const std::size_t largeCount = (kLargeBufferBytes + sizeof(T) - 1) / sizeof(T);
    buffer.reserve(count * sizeof(T) >= (kLargeBufferBytes >> 2) ? std::max(count, largeCount)
                                                                 : count);
  };
  if (direct) {
    reserveOutput(positions, room[0]);
  } else {
    vertices.reserve(room[0]);
  }
  reserveOutput(triangles, room[1]);
  loopVertices.reserve(room[2]);
  if (direct && shared) centreEntry.reserve(room[3]);
  return slabBricks;
}

// The totals kept for the next run's room, outputs trimmed, and the bricks' triangle ranges.
void Builder::finish(std::size_t n, Buffer<VertexInfo>& vertices, Buffer<glm::dvec3>& positions,
                     Buffer<glm::u32vec3>& triangles,
                     std::vector<SurfaceMesh::BrickRange>& ranges) {
  lastTotals = {vertexOffset[n], triOffset[n], loopOffset[n], centreOffset[n]};
  // A mesh far smaller than the last does not keep the last one's room, but for one 2 MiB
  // block (reserveOutput's): a copy would fault in its pages again.
  const auto fit = [](auto& buffer) {
    using T = typename std::decay_t<decltype(buffer)>::value_type;
    if (buffer.capacity() > 2 * buffer.size() + 4096 &&
        buffer.capacity() * sizeof(T) > 2 * kLargeBufferBytes)
      buffer.shrink_to_fit();
  };
  fit(positions);
  fit(vertices);
  fit(triangles);
  ranges.reserve(ranges.size() + n);  // one allocation, not a dozen regrowths
  for (std::size_t s = 0; s < n; ++s) {
    if (triOffset[s + 1] > triOffset[s]) {
      ranges.push_back({std::int64_t(cellBrickIndex(active[s])), active[s], triOffset[s],
                        triOffset[s + 1] - triOffset[s]});
    }
  }
}

void Builder::run(Buffer<VertexInfo>& vertices, Buffer<glm::dvec3>& positions,
                  Buffer<std::uint32_t>& loopVertices, Buffer<glm::u32vec3>& triangles,
                  std::vector<SurfaceMesh::BrickRange>& ranges) {
  // With one thread allowed, plain loops: TBB's tasks and partitioner cost a single thread
  // time and buy it nothing (a 64^3 extraction runs 27 loops, three per slab).
  const bool serial = oneThreadAllowed();
  const auto forEachBrickIn = [&](std::size_t first, std::size_t last, auto&& work) {
    if (serial) {
      for (std::size_t s = first; s < last; ++s) work(s);
      return;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 4),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t s = r.begin(); s != r.end(); ++s) work(s);
                      });
  };
  // Slab by slab (a z layer of cell bricks): which cell bricks hold surface and pass 1 on
  // them, their places in the output, then the slab below's vertices, ids and triangles
  // (its cells share edges with this slab, numbered just now), then the loop centres of the
  // slab below that (their loops reach into the slab above them). What each step reads
  // was made a moment before and is still in cache. Numbering follows brick order (a
  // brick's edge vertices, then its loop centres), so it does not depend on scheduling.
  const std::size_t slabBricks = prepare(vertices, positions, loopVertices, triangles);
  const auto brick = [&](std::size_t s) {
    if (!shared) {
      writeTrianglesNaive(s, vertices, positions, loopVertices, triangles);
    } else if (direct) {
      writeBrick<true>(s, nullptr, positions.data(), loopVertices.data(), centreEntry.data(),
                       triangles.data());
    } else {
      writeBrick<false>(s, vertices.data(), nullptr, loopVertices.data(), nullptr,
                        triangles.data());
    }
  };
  const auto centres = [&](std::size_t s) {
    placeCentres(s, positions.data(), loopVertices.data(), centreEntry.data());
  };
  const bool placeLater = direct && shared;
  ActiveBrickScan scan(grid, brickStates, brickRowBits);
  std::size_t written = 0, placed = 0;  // bricks before these are written, have their centres
  for (int z = -1; z + 1 < cellBricks.z; ++z) {
    const std::size_t first = active.size();
    scan.slab(z, active);
    const std::size_t last = active.size();
    for (std::size_t s = first; s < last; ++s)
      ring.push_back(std::uint32_t(((z + 1) & 1) * slabBricks + (s - first)));
    forEachBrickIn(first, last, [&](std::size_t s) { count(s, scan); });
    for (std::size_t s = first; s < last; ++s) {
      const BrickOut& o = out[ring[s]];
      slotOfBrick[cellBrickIndex(active[s])] = std::int32_t(ring[s]);
      index[ring[s]].firstEdgeVertex = vertexOffset[s];
      extraOffset.push_back(vertexOffset[s] + o.edges);
      vertexOffset.push_back(extraOffset[s] + o.extras);
      centreOffset.push_back(centreOffset[s] + o.extras);
      triOffset.push_back(triOffset[s] + o.triangles);
      loopOffset.push_back(loopOffset[s] + o.loopEntries);
    }
    // Past the room reserved, regrow once for the whole grid, projected from the cell layers
    // done (a volume of noise, some 1,000 vertices per stored brick, shows on its first
    // slabs), rather than by doubling, each step of which is a fresh allocation and a copy.
    const double layersDone =
        std::min(kBrickEdge * (z + 1) + 1, dims.z + 1);  // cell layers -1 .. 8 z + 7
    const auto grow = [&](auto& buffer, std::size_t size) {
      if (size > buffer.capacity()) {
        buffer.reserve(std::size_t(double(size) * double(dims.z + 1) / layersDone * 1.25) + 1024);
      }
      buffer.resize(size);
    };
    if (direct) {
      grow(positions, vertexOffset[last]);
    } else {
      grow(vertices, vertexOffset[last]);
    }
    grow(triangles, triOffset[last]);
    grow(loopVertices, loopOffset[last]);
    if (placeLater) grow(centreEntry, centreOffset[last]);
    forEachBrickIn(written, first, brick);
    if (placeLater) forEachBrickIn(placed, written, centres);
    placed = written;
    written = first;
  }
  const std::size_t n = active.size();
  forEachBrickIn(written, n, brick);
  if (placeLater) {
    forEachBrickIn(placed, written, centres);
    forEachBrickIn(written, n, centres);
  }
  finish(n, vertices, positions, triangles, ranges);
}

}  // namespace detail

using namespace detail;

void validateSurfaceOptions(const SurfaceOptions& options) {
  if (options.smoothIterations < 0 || options.smoothIterations > 100) {
    throw OptionError("smoothIterations", std::to_string(options.smoothIterations),
                      "passes must be 0..100");
  }
  if (!(options.lambda > 0.0 && options.lambda <= 1.0) ||
      !(options.mu < 0.0 && options.mu >= -1.0)) {
    std::ostringstream s;
    s << "smoothing weights lambda " << options.lambda << ", mu " << options.mu
      << ": need 0 < lambda <= 1 and -1 <= mu < 0";
    throw InputError(s.str());
  }
}

SurfaceMesh extractSurface(const VoxelGrid& grid, const SurfaceOptions& options,
                           SurfaceTimings* timings) {
  validateSurfaceOptions(options);
  SurfaceTimings local;
  const Clock::time_point start = Clock::now();
  Buffer<VertexInfo> vertices;
  Buffer<std::uint32_t> loopVertices;
  Buffer<glm::u32vec3> triangles;
  std::vector<SurfaceMesh::BrickRange> ranges;
  SurfaceMesh mesh;
  bool direct = false;
  {
    Builder builder(grid, options);
    builder.run(vertices, mesh.positionsMm, loopVertices, triangles, ranges);
    direct = builder.direct;
  }
  local.extractMs = msSince(start);

  if (direct) {
    const Clock::time_point phase = Clock::now();
    if (options.computeNormals) areaWeightedNormals(mesh.positionsMm, triangles, mesh.normals);
    local.normalsMs = msSince(phase);
  } else {
    finishSurface(vertices, loopVertices, triangles,
                  {options.smoothIterations, options.lambda, options.taubin, options.mu,
                   options.computeNormals},
                  mesh.positionsMm, mesh.normals, local.otherMs, local.smoothMs, local.normalsMs);
  }
  mesh.triangles = std::move(triangles);
  mesh.brickRanges = std::move(ranges);
  local.totalMs = msSince(start);
  if (timings) *timings = local;
  return mesh;
}

}  // namespace osteon::geometry
