// How the incremental updater stores its surface compactly and without stalls: per-slot arrays
// in fixed pages (growing one never copies what is there, so no update waits on a copy of the
// whole surface), a vertex slot in 24 bytes (its position is derived from the grid), and a cell
// brick's owned edge vertices as a bit mask with ranks instead of a dense table (most of its
// 1,536 edges cross no surface).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

#include <glm/vec3.hpp>

namespace osteon::geometry::updater_detail {

// Bits set in x, inline on every x86-64 (the builtin is a library call without -mpopcnt).
inline int popcount64(std::uint64_t x) {
  x = x - ((x >> 1) & 0x5555555555555555ull);
  x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
  x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0full;
  return int((x * 0x0101010101010101ull) >> 56);
}

// An array of T in pages of 2^kPageLog2 elements: indexing is one more load than a vector's,
// and growing allocates one page, never moving the elements already stored.
template <typename T>
class PagedArray {
 public:
  static constexpr int kPageLog2 = 14;
  static constexpr std::size_t kPageSize = std::size_t(1) << kPageLog2;

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T& operator[](std::size_t i) { return pages_[i >> kPageLog2].get()[i & (kPageSize - 1)]; }
  const T& operator[](std::size_t i) const {
    return pages_[i >> kPageLog2].get()[i & (kPageSize - 1)];
  }
  // Pages for `count` elements allocated now (the first extraction sizes every array once).
  void reserve(std::size_t count) {
    while (pages_.size() * kPageSize < count)
      pages_.push_back(Page(static_cast<T*>(::operator new(kPageSize * sizeof(T)))));
  }
  // Grows to `count`, the new elements left for the caller to write (in parallel: distinct
  // elements of a sized array may be written from distinct threads).
  void growTo(std::size_t count) {
    reserve(count);
    size_ = std::max(size_, count);
  }
  // Grows or shrinks to `count`; new elements are `value`.
  void resize(std::size_t count, const T& value = T()) {
    reserve(count);
    for (std::size_t i = size_; i < count; ++i) (*this)[i] = value;
    size_ = count;
  }
  void push_back(const T& value) {
    reserve(size_ + 1);
    (*this)[size_++] = value;
  }
  void assign(std::size_t count, const T& value) {
    size_ = 0;
    resize(count, value);
  }
  std::size_t memoryBytes() const {
    return pages_.size() * kPageSize * sizeof(T) + pages_.capacity() * sizeof(pages_[0]);
  }

 private:
  // Pages are storage only, never constructed: every element is written before it is read
  // (growTo's callers, resize, push_back), so a fresh page is not filled twice.
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>,
                "a page holds plain values");
  struct Free {
    void operator()(T* p) const { ::operator delete(p); }
  };
  using Page = std::unique_ptr<T, Free>;
  std::vector<Page> pages_;
  std::size_t size_ = 0;
};

// A vertex slot: an edge vertex (axis 0-2) on the edge from the centre of `voxel` to the next
// voxel along `axis`, at parameter t; or a loop centre (axis 3) in cell `voxel`, its loop's
// vertices in the centre loops at `loop`. 24 bytes: the position is the grid's to compute.
struct SlotInfo {
  glm::ivec3 voxel{0};
  std::uint8_t axis = 0;
  std::uint8_t loopSize = 0;  // centres: vertices in the loop
  union {
    double t = 0.0;      // edge vertices
    std::uint32_t loop;  // centres: first of loopSize entries in the centre loops
  };
};
static_assert(sizeof(SlotInfo) == 24, "a vertex slot stays 24 bytes");

// A loop centre in `cell` over `count` vertices kept at `loop` in the centre loops.
inline SlotInfo centreSlot(const glm::ivec3& cell, int count, std::uint32_t loop) {
  SlotInfo v;
  v.voxel = cell;
  v.axis = 3;
  v.loopSize = std::uint8_t(count);
  v.loop = loop;
  return v;
}

// The vertex slots of a cell brick's owned edges (edge 3 * cell + axis), kept as a mask of the
// edges that have one and their slots in edge order: rank(e) = owned edges before e.
class OwnedEdges {
 public:
  static constexpr int kEdges = 3 * 512;
  static constexpr int kWords = kEdges / 64;
  static constexpr std::uint32_t kNone = 0xffffffffu;

  std::uint32_t get(int e) const {
    const int w = e >> 6;
    const std::uint64_t bit = std::uint64_t(1) << (e & 63);
    if (!(mask_[std::size_t(w)] & bit)) return kNone;
    return slots_[std::size_t(before_[std::size_t(w)]) +
                  std::size_t(popcount64(mask_[std::size_t(w)] & (bit - 1)))];
  }
  std::size_t count() const { return slots_.size(); }
  const std::vector<std::uint32_t>& slots() const { return slots_; }
  std::vector<std::uint32_t>& slots() { return slots_; }
  // Every owned edge with its slot, in edge order.
  template <typename Fn>
  void forEach(Fn&& fn) const {
    std::size_t k = 0;
    for (int w = 0; w < kWords; ++w)
      for (std::uint64_t m = mask_[std::size_t(w)]; m; m &= m - 1)
        fn(64 * w + __builtin_ctzll(m), slots_[k++]);
  }
  // From a dense table (kNone: no vertex), slots in edge order.
  void assign(const std::array<std::uint32_t, kEdges>& dense) {
    slots_.clear();
    for (int w = 0; w < kWords; ++w) {
      before_[std::size_t(w)] = std::uint16_t(slots_.size());
      std::uint64_t m = 0;
      for (int b = 0; b < 64; ++b) {
        const std::uint32_t s = dense[std::size_t(64 * w + b)];
        if (s == kNone) continue;
        m |= std::uint64_t(1) << b;
        slots_.push_back(s);
      }
      mask_[std::size_t(w)] = m;
    }
  }
  // Into a dense table.
  void expand(std::array<std::uint32_t, kEdges>& dense) const {
    dense.fill(kNone);
    forEach([&](int e, std::uint32_t s) { dense[std::size_t(e)] = s; });
  }
  // The mask of edges with a vertex (bit e % 64 of word e / 64), its slots still to be written
  // (in edge order) by the caller: the first extraction sets which edges cross before any slot
  // is numbered.
  void setMask(const std::array<std::uint64_t, kWords>& crossed) {
    std::size_t n = 0;
    for (int w = 0; w < kWords; ++w) {
      before_[std::size_t(w)] = std::uint16_t(n);
      mask_[std::size_t(w)] = crossed[std::size_t(w)];
      n += std::size_t(popcount64(crossed[std::size_t(w)]));
    }
    slots_.assign(n, kNone);
  }
  std::size_t memoryBytes() const {
    return sizeof(*this) + slots_.capacity() * sizeof(std::uint32_t);
  }

 private:
  // Not zeroed by default: a cell brick's are (CellBrick), or setMask or assign writes them.
  std::array<std::uint64_t, kWords> mask_;
  std::array<std::uint16_t, kWords> before_;
  std::vector<std::uint32_t> slots_;
};

}  // namespace osteon::geometry::updater_detail
