// The case tables of the full surface extractor (surface_extract.cpp): the layout of a brick's
// edge-id table, each case as slot offsets into it, the cases' counts, and bit-count tables.
#pragma once

#include <array>
#include <cstdint>

#include "surface_cells.h"

namespace osteon::geometry::detail {

// A brick's triangle pass has the ids of every edge its cells can use in one table in L1
// cache: the brick's own edges (as its vertices are made) and those its cells share on its
// upper faces with the bricks above, slot ((z * 9 + y) * 3 + axis) * 9 + x for the edge from
// block voxel (x, y, z) along axis.
// A cell's edge e is then at a fixed offset from the cell's own slot, so a case's triangles
// read their ids straight from the table.
inline constexpr int kSlotsPerRow = 3 * kBlock;
inline constexpr int kIdSlots = kBlock * kBlock * kSlotsPerRow;
using EdgeIds = std::array<std::uint32_t, kIdSlots>;
constexpr int idSlot(int x, int y, int z, int axis) {
  return ((z * kBlock + y) * 3 + axis) * kBlock + x;
}

// For cube edge e of a cell, its slot's offset from the cell's slot (axis 0).
inline constexpr std::array<std::uint16_t, 12> kEdgeSlot = [] {
  std::array<std::uint16_t, 12> t{};
  for (int e = 0; e < 12; ++e) {
    const auto& o = kEdgeStartOffset[std::size_t(e)];
    t[std::size_t(e)] = std::uint16_t(idSlot(o[0], o[1], o[2], e / 4));
  }
  return t;
}();

// A case as pass 3 writes it, its edges as slot offsets in the id table (kEdgeSlot). Without
// a long loop: its triangles' corners, three per triangle (a triangle; a quad split from its
// first corner; slots past the last triangle repeat the first). With one: its loops' edges in
// order and their lengths, since a loop of five or more edges fans around a centre vertex
// made with it. Twelve slots hold either (at most four triangles without a long loop; at most
// twelve crossed edges), so a case is 32 bytes: the table (8 KiB) stays in L1 cache and a
// case is found with a shift.
struct FlatCase {
  std::uint8_t triangleCount = 0;
  std::uint8_t longLoops = 0;
  std::uint8_t loopCount = 0;
  std::array<std::uint8_t, 4> loopLength{};
  std::array<std::uint16_t, 12> slots{};
};
static_assert(sizeof(FlatCase) == 32, "a case is half a cache line");

const std::array<FlatCase, 256>& flatCases();

// What each case adds, in the 16-bit lanes of one word: triangles, loop-centre vertices,
// centre-loop entries, loop corners. A cell adds them with one addition (a brick's 512 cells
// add at most 12 each).
const std::array<std::uint64_t, 256>& packedCaseCounts();

// Set bits of each byte value.
inline constexpr std::array<std::uint8_t, 256> kBitsInByte = [] {
  std::array<std::uint8_t, 256> t{};
  for (int v = 0; v < 256; ++v)
    t[std::size_t(v)] =
        std::uint8_t((v & 1) + ((v >> 1) & 1) + ((v >> 2) & 1) + ((v >> 3) & 1) + ((v >> 4) & 1) +
                     ((v >> 5) & 1) + ((v >> 6) & 1) + ((v >> 7) & 1));
  return t;
}();

// For each byte of crossings, the crossings below each bit x (8 KiB, read as two vectors).
struct alignas(16) BelowRow : std::array<std::uint32_t, kCellBrick> {};
inline constexpr std::array<BelowRow, 256> kCrossingsBelow = [] {
  std::array<BelowRow, 256> t{};
  for (std::uint32_t b = 0; b < 256; ++b)
    for (std::uint32_t x = 0, n = 0; x < std::uint32_t(kCellBrick); n += (b >> x) & 1u, ++x)
      t[b][x] = n;
  return t;
}();

}  // namespace osteon::geometry::detail
