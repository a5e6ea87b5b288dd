// What pass 1 of the full extractor (surface_extract.cpp) finds per active cell brick and the
// later passes read: where its fills are, its counts, its rows of cells with surface and their
// cases, and the crossings of the edges it owns, numbered.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "surface_cells.h"

namespace osteon::geometry::detail {

// A layer's eight rows of bytes (mixed cells, crossings) are read as one 64-bit word, bit
// x + 8 y, and a row's cases as bytes of its word: little-endian byte order.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "bricks' bytes are read as little-endian words");

// Per active cell brick: where its fills are, how much it adds, and its rows of cells with
// surface, each row's mixed cells and their cases.
struct BrickOut {
  // Left uninitialised: every brick fills its arrays before reading them, so zeroing some
  // 8 KiB per active brick up front would be pure cost.
  BrickOut() {}  // NOLINT: deliberately not = default (that would zero the arrays)
  BlockSource source;
  std::uint32_t edges, extras, triangles, loopEntries;  // counts
  std::uint64_t surfaceRows;   // bit ly + 8 lz: the row has a mixed cell (pass 1 finds them)
  std::uint64_t lastCellRows;  // and its last cell (x = 7) is mixed: it uses the +x brick's edges
  // Byte ly + 8 lz: the row's mixed cells as x bits (all eight rows of a surface layer, so a
  // layer reads as one 64-bit word, bit x + 8 y).
  std::array<std::uint8_t, kCellBrick * kCellBrick> mixed;
  std::array<std::uint64_t, kCellBrick * kCellBrick>
      configs;  // byte x: cell x's case (surface rows)

  // Bit lz: layer lz has a surface row (a nonzero byte of surfaceRows).
  std::uint32_t surfaceLayers() const {
    std::uint64_t t = surfaceRows;
    t |= t >> 4;
    t |= t >> 2;
    t |= t >> 1;  // bit 8 lz: any bit of byte lz
    return std::uint32_t(((t & 0x0101010101010101ull) * 0x0102040810204080ull) >> 56);
  }
};

// Edge vertices are numbered layer by layer (z), axis by axis, row by row (y), x by x: the
// order of the bits of a layer's three 64-bit words of crossings (edgeByte), which pass 2
// walks one word at a time. So the vertex of an owned edge is firstEdgeVertex + the crossings
// before its (row, axis) byte + those of lower x in it. Pass 1 writes a layer's bytes at once,
// and only for layers with a mixed cell (later passes read no other): 580 bytes per brick,
// kept apart from the bulky BrickOut so that the neighbours' indices pass 3 reads stay in
// cache, where a table of every edge's id (3-6 KiB per brick) would not.
constexpr std::size_t edgeByte(int row, int axis) {  // row = ly + 8 lz
  return std::size_t(3 * kCellBrick * (row >> 3) + kCellBrick * axis + (row & (kCellBrick - 1)));
}

struct EdgeIndex {
  EdgeIndex() {}                  // NOLINT: left uninitialised, as BrickOut
  std::uint32_t firstEdgeVertex;  // global id of the brick's first
  std::array<std::uint8_t, 3 * kCellBrick * kCellBrick>
      crossings;  // bit x: the edge of cell x crosses
  std::array<std::uint16_t, 3 * kCellBrick * kCellBrick> crossingsBefore;
};

// Pass 1 on one active cell brick (surface_count.cpp): its block's inside bits (from the scan
// for a dense block), its mixed cells and their cases, its owned edges' crossings and their
// prefix counts, and what it adds to the output (shared: one vertex per crossed edge, the
// crack-free method; else every cell's own).
void countBrick(const VoxelGrid& grid, const ActiveBrickScan& scan, const glm::ivec3& cellBrick,
                bool shared, BrickOut& out, EdgeIndex& index);

}  // namespace osteon::geometry::detail
