#include "surface_upload.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "field_normals.h"

namespace osteon::viewer {

namespace {

GpuVertex toGpu(const glm::dvec3& p, const glm::dvec3& n) {
  return {{float(p.x), float(p.y), float(p.z)}, {float(n.x), float(n.y), float(n.z)}};
}

GpuVertex deadVertex() {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  return {{nan, nan, nan}, {0.0f, 0.0f, 1.0f}};
}

// The smallest power-of-two multiple of `minimum` that holds `needed` with a quarter spare.
std::size_t grownCapacity(std::size_t current, std::size_t minimum, std::size_t needed) {
  std::size_t capacity = std::max(current, minimum);
  while (capacity < needed + needed / 4) capacity *= 2;
  return capacity;
}

}  // namespace

std::size_t SurfaceUploader::withSpare(std::size_t count) {
  return count + std::max(kMinSpareTriangles, std::size_t(double(count) * kSpareFraction));
}

void SurfaceUploader::reset() {
  vertices_.clear();
  indices_.clear();
  regions_.clear();
  free_.clear();
  slotCount_ = vertexCapacity_ = 0;
  endTriangles_ = capacityTriangles_ = liveTriangles_ = 0;
  started_ = false;
}

const UploadStats& SurfaceUploader::apply(const geometry::SurfaceDelta& delta) {
  stats_ = UploadStats{};
  const bool everything = delta.everything || !started_;
  if (everything) reset();
  started_ = true;
  applyVertices(delta, everything);
  if (!everything) {
    for (const geometry::SurfaceDelta::Brick& b : delta.bricks) applyBrick(b.key, b.triangles);
    return stats_;
  }
  // Everything: the bricks laid out in key order, each with its spare room, uploaded once.
  std::vector<const geometry::SurfaceDelta::Brick*> bricks;
  bricks.reserve(delta.bricks.size());
  for (const geometry::SurfaceDelta::Brick& b : delta.bricks) {
    if (!b.triangles.empty()) bricks.push_back(&b);
  }
  std::sort(bricks.begin(), bricks.end(), [](auto* a, auto* b) { return a->key < b->key; });
  std::size_t end = 0;
  for (const auto* b : bricks) end += withSpare(b->triangles.size());
  capacityTriangles_ = grownCapacity(0, kMinIndexCapacity / 3, end);
  indices_.assign(3 * capacityTriangles_, 0u);
  for (const auto* b : bricks) {
    Region r{endTriangles_, withSpare(b->triangles.size()), b->triangles.size()};
    std::copy_n(&b->triangles[0].x, 3 * r.count, indices_.begin() + std::ptrdiff_t(3 * r.first));
    regions_[b->key] = r;
    endTriangles_ += r.capacity;
    liveTriangles_ += r.count;
  }
  // Whole, padding included: regions later appended past the end are then degenerate on the
  // GPU until written.
  target_->reallocateIndices(3 * capacityTriangles_, indices_.data(), 3 * capacityTriangles_);
  ++stats_.indexReallocations;
  stats_.indicesWritten += 3 * capacityTriangles_;
  return stats_;
}

void SurfaceUploader::applyVertices(const geometry::SurfaceDelta& delta, bool everything) {
  if (delta.slotCount > slotCount_) {
    vertices_.resize(delta.slotCount, deadVertex());
    slotCount_ = delta.slotCount;
  }
  for (std::size_t i = 0; i < delta.slots.size(); ++i) {
    const std::uint32_t slot = delta.slots[i];
    if (slot >= slotCount_) continue;  // a delta never lists one; guard the mirror anyway
    const glm::dvec3& p = delta.positionsMm[i];
    if (!std::isfinite(p.x)) {
      vertices_[slot] = deadVertex();
      continue;
    }
    const glm::dvec3 n = i < delta.normals.size() ? delta.normals[i] : glm::dvec3(0.0);
    vertices_[slot] = toGpu(p, field_ ? fieldNormal(*field_, p, n) : n);
  }
  if (everything || slotCount_ > vertexCapacity_) {
    vertexCapacity_ = grownCapacity(vertexCapacity_, kMinVertexCapacity, slotCount_);
    target_->reallocateVertices(vertexCapacity_, vertices_.data(), slotCount_);
    ++stats_.vertexReallocations;
    stats_.verticesWritten += slotCount_;
    return;
  }
  // Only the listed slots, as runs.
  changedSlots_.assign(delta.slots.begin(), delta.slots.end());
  std::sort(changedSlots_.begin(), changedSlots_.end());
  changedSlots_.erase(std::unique(changedSlots_.begin(), changedSlots_.end()), changedSlots_.end());
  for (std::size_t i = 0; i < changedSlots_.size();) {
    std::size_t j = i + 1;
    while (j < changedSlots_.size() && changedSlots_[j] - changedSlots_[j - 1] <= kMergeGap) ++j;
    const std::size_t first = changedSlots_[i], count = changedSlots_[j - 1] - first + 1;
    if (first < slotCount_) {
      const std::size_t n = std::min(count, slotCount_ - first);
      target_->writeVertices(first, n, vertices_.data() + first);
      ++stats_.vertexWrites;
      stats_.verticesWritten += n;
    }
    i = j;
  }
}

void SurfaceUploader::pad(std::size_t firstTriangle, std::size_t triangles) {
  std::fill_n(indices_.begin() + std::ptrdiff_t(3 * firstTriangle), 3 * triangles, 0u);
}

void SurfaceUploader::writeTriangles(const Region& r, std::size_t triangles) {
  if (triangles == 0) return;
  target_->writeIndices(3 * r.first, 3 * triangles, indices_.data() + 3 * r.first);
  ++stats_.indexWrites;
  stats_.indicesWritten += 3 * triangles;
}

void SurfaceUploader::applyBrick(std::int64_t key, const std::vector<glm::u32vec3>& triangles) {
  const std::size_t n = triangles.size();
  auto it = regions_.find(key);
  if (it == regions_.end() && n == 0) return;
  std::size_t old = 0;
  if (it != regions_.end()) {
    Region& r = it->second;
    old = r.count;
    if (n <= r.capacity) {
      // In place: the new triangles, then degenerate ones over what the brick used before.
      if (n > 0)
        std::copy_n(&triangles[0].x, 3 * n, indices_.begin() + std::ptrdiff_t(3 * r.first));
      if (old > n) pad(r.first + n, old - n);
      r.count = n;
      writeTriangles(r, std::max(n, old));
      liveTriangles_ = liveTriangles_ + n - old;
      return;
    }
    // Outgrown: the old region is cleared and freed.
    pad(r.first, old);
    writeTriangles(r, old);
    free_.push_back({r.first, r.capacity, 0});
    regions_.erase(it);
    liveTriangles_ -= old;
    ++stats_.bricksMoved;
  }
  Region r = allocate(withSpare(n), key);
  r.count = n;
  std::copy_n(&triangles[0].x, 3 * n, indices_.begin() + std::ptrdiff_t(3 * r.first));
  regions_[key] = r;
  liveTriangles_ += n;
  writeTriangles(r, n);
}

SurfaceUploader::Region SurfaceUploader::allocate(std::size_t need, std::int64_t forKey) {
  // The best fitting free region; one more than twice too large is split.
  std::size_t best = free_.size();
  for (std::size_t i = 0; i < free_.size(); ++i) {
    if (free_[i].capacity >= need &&
        (best == free_.size() || free_[i].capacity < free_[best].capacity))
      best = i;
  }
  if (best < free_.size()) {
    Region r = free_[best];
    free_.erase(free_.begin() + std::ptrdiff_t(best));
    if (r.capacity > 2 * need) {
      free_.push_back({r.first + need, r.capacity - need, 0});
      r.capacity = need;
    }
    return r;
  }
  if (endTriangles_ + need > capacityTriangles_) repack(need, forKey);
  Region r{endTriangles_, need, 0};
  endTriangles_ += need;
  return r;
}

void SurfaceUploader::repack(std::size_t extraTriangles, std::int64_t skipKey) {
  // Every brick again in key order with fresh spare room; free regions vanish.
  std::vector<std::pair<std::int64_t, Region>> order(regions_.begin(), regions_.end());
  std::sort(order.begin(), order.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::size_t end = 0;
  for (const auto& [key, r] : order) {
    if (key != skipKey) end += withSpare(r.count);
  }
  const std::size_t capacity =
      grownCapacity(capacityTriangles_, kMinIndexCapacity / 3, end + extraTriangles);
  std::vector<std::uint32_t> packed(3 * capacity, 0u);
  std::size_t at = 0;
  for (auto& [key, r] : order) {
    if (key == skipKey) continue;
    std::copy_n(indices_.begin() + std::ptrdiff_t(3 * r.first), 3 * r.count,
                packed.begin() + std::ptrdiff_t(3 * at));
    Region moved{at, withSpare(r.count), r.count};
    regions_[key] = moved;
    at += moved.capacity;
  }
  indices_.swap(packed);
  free_.clear();
  capacityTriangles_ = capacity;
  endTriangles_ = at;
  target_->reallocateIndices(3 * capacityTriangles_, indices_.data(), 3 * capacityTriangles_);
  ++stats_.indexReallocations;
  stats_.indicesWritten += 3 * capacityTriangles_;
}

}  // namespace osteon::viewer
