// The incremental upload of the live surface, as plain bookkeeping with no GL call: what to
// write where in a vertex buffer indexed by slot and an index buffer of one region per cell
// brick. The renderer's GL buffers implement SurfaceUploadTarget; a test implements it over
// plain arrays and checks the result against a full upload (SurfaceUpdater::mesh()).
//
// Vertex buffer: slot i of the updater's stable numbering at element i. Its capacity grows by
// doubling when slotCount passes it (then the whole mirror is uploaded once); otherwise only
// the changed slots are written, as runs (slots closer than kMergeGap apart share one write).
// Dead slots hold NaN positions; no triangle refers to them.
//
// Index buffer: each cell brick owns a region of triangles [first, first + capacity) with
// spare room (count x kSpareFraction, at least kMinSpareTriangles). A changed brick is
// rewritten in place when its triangles fit, the rest of what it used padded with degenerate
// triangles (0, 0, 0); a brick that outgrows its region moves to a free region or the end,
// and its old region, padded, becomes free. Only when the end passes the capacity is the
// buffer repacked whole (capacity doubled if needed) and uploaded once, padding included, so
// every index past the end is degenerate on the GPU before a region is placed there.
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

#include "osteon/geometry/surface/surface_updater.h"

namespace osteon::viewer {

struct GpuVertex {
  float position[3];  // mm, NaN for a dead slot
  float normal[3];
};
static_assert(sizeof(GpuVertex) == 24, "tightly packed for the vertex buffer");

// Where the bookkeeping writes (GL buffers in the renderer). Counts are in elements:
// vertices, or uint32 indices (three per triangle).
class SurfaceUploadTarget {
 public:
  virtual ~SurfaceUploadTarget() = default;
  // New storage of `capacity` vertices holding data[0, count); the rest is undefined.
  virtual void reallocateVertices(std::size_t capacity, const GpuVertex* data,
                                  std::size_t count) = 0;
  virtual void writeVertices(std::size_t first, std::size_t count, const GpuVertex* data) = 0;
  // New storage of `capacity` indices holding data[0, count); the rest is undefined.
  virtual void reallocateIndices(std::size_t capacity, const std::uint32_t* data,
                                 std::size_t count) = 0;
  virtual void writeIndices(std::size_t first, std::size_t count, const std::uint32_t* data) = 0;
};

// What one apply() did.
struct UploadStats {
  std::size_t vertexWrites = 0, verticesWritten = 0;
  std::size_t indexWrites = 0, indicesWritten = 0;
  std::size_t vertexReallocations = 0, indexReallocations = 0;  // whole-buffer uploads
  std::size_t bricksMoved = 0;                                  // bricks that outgrew their region
  std::size_t bytes() const { return verticesWritten * sizeof(GpuVertex) + indicesWritten * 4; }
};

class SurfaceUploader {
 public:
  static constexpr std::size_t kMinVertexCapacity = 1024;
  static constexpr std::size_t kMinIndexCapacity = 3 * 4096;
  static constexpr double kSpareFraction = 0.5;
  static constexpr std::size_t kMinSpareTriangles = 32;
  static constexpr std::size_t kMergeGap = 8;

  explicit SurfaceUploader(SurfaceUploadTarget& target) : target_(&target) {}

  // Applies the changes (a delta with `everything` starts over: both buffers uploaded whole).
  const UploadStats& apply(const geometry::SurfaceDelta& delta);
  // Forgets the surface (a new bone); the next delta must have `everything`.
  void reset();
  // Shade with normals from this grid's fill gradient (field_normals.h) instead of the
  // delta's; null (the default) keeps the delta's. Positions are never touched. The grid must
  // be up to date with the deltas applied (the visual side's grid, on its thread).
  void setNormalField(const geometry::VoxelGrid* grid) { field_ = grid; }

  // The mirror of the GPU's index buffer, and what to draw: indices [0, indexEnd()).
  const std::vector<std::uint32_t>& indices() const { return indices_; }
  std::size_t indexEnd() const { return 3 * endTriangles_; }
  std::size_t triangleCount() const { return liveTriangles_; }

 private:
  struct Region {
    std::size_t first = 0;  // in triangles
    std::size_t capacity = 0;
    std::size_t count = 0;
  };
  static std::size_t withSpare(std::size_t count);
  void applyVertices(const geometry::SurfaceDelta& delta, bool everything);
  void applyBrick(std::int64_t key, const std::vector<glm::u32vec3>& triangles);
  // A region of at least `need` triangles: a free one, the end, or after a repack.
  Region allocate(std::size_t need, std::int64_t forKey);
  void repack(std::size_t extraTriangles, std::int64_t skipKey);
  void writeTriangles(const Region& r, std::size_t triangles);
  void pad(std::size_t firstTriangle, std::size_t triangles);

  SurfaceUploadTarget* target_;
  const geometry::VoxelGrid* field_ = nullptr;
  std::vector<GpuVertex> vertices_;
  std::vector<std::uint32_t> indices_;
  std::size_t slotCount_ = 0, vertexCapacity_ = 0;
  std::size_t endTriangles_ = 0, capacityTriangles_ = 0, liveTriangles_ = 0;
  std::unordered_map<std::int64_t, Region> regions_;
  std::vector<Region> free_;
  std::vector<std::uint32_t> changedSlots_;
  UploadStats stats_;
  bool started_ = false;
};

}  // namespace osteon::viewer
