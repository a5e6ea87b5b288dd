// Pass 1 of the full extractor (surface_extract.cpp): per active cell brick, its block's
// inside bits, its mixed cells and their cases, the crossings of the edges it owns, and what
// it adds to the output.
#include <array>
#include <cstdint>

#include "osteon/core/constants.h"
#include "surface_bricks.h"
#include "surface_cases.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace osteon::geometry::detail {

// A row's inside bits spread by table into one bit pair per byte, four rows shifted in.
std::uint64_t rowConfigs(const std::uint32_t (&r)[4]) {
  static const std::array<std::uint64_t, 512> spread = [] {
    std::array<std::uint64_t, 512> t{};
    for (std::uint32_t bits = 0; bits < 512; ++bits)
      for (int x = 0; x < kCellBrick; ++x) t[bits] |= std::uint64_t((bits >> x) & 3u) << (8 * x);
    return t;
  }();
  return spread[r[0]] | (spread[r[1]] << 2) | (spread[r[2]] << 4) | (spread[r[3]] << 6);
}

namespace {

// The cells of a row range whose x lies in [xLo, xHi) (block-local), as a bit mask.
inline std::uint32_t xRange(int xLo, int xHi) {
  return xHi <= xLo ? 0u : ((1u << xHi) - 1u) & ~((1u << xLo) - 1u);
}

// Inside bits of a block at the grid's border (one that is not dense, often holding a single
// layer of the grid), one 9-bit word per (y, z) row, straight from the grid's bricks (a row's
// first eight voxels are one brick row: one vector compare): only the rows inside the grid
// are read, clipped along x; the rest stay 0.
void insideRows(const BlockSource& src, RowMasks& rows) {
  rows.fill(0);
  const std::uint32_t xValid = xRange(src.lo.x, src.hi.x);
  for (int z = src.lo.z; z < src.hi.z; ++z)
    for (int y = src.lo.y; y < src.hi.y; ++y) {
      const auto d = std::size_t(((y >> 3) << 1) | ((z >> 3) << 2));
      const int row = kCellBrick * ((y & 7) + kCellBrick * (z & 7));
      std::uint32_t m =
          src.data[d] ? insideOf8(src.data[d] + row) : (src.uniform[d] > kInsideAbove ? 0xffu : 0u);
      const Fill next = src.data[d | 1] ? src.data[d | 1][row] : src.uniform[d | 1];
      m |= (next > kInsideAbove ? 1u : 0u) << 8;
      rows[std::size_t(y + kBlock * z)] = std::uint16_t(m & xValid);
    }
}

// A dense block's rows of inside bits from those the scan kept for its eight grid bricks
// (octant d: +x if d & 1, +y if d & 2, +z if d & 4): each row's first eight from its brick,
// the ninth from the first of the brick along +x: a few vector steps per block instead of a
// compare of fills per row (81 rows), since the scan has already made those compares.
void insideRowsFromScan(const ActiveBrickScan& scan, const glm::ivec3& cb, RowMasks& rows) {
  const ActiveBrickScan::RowBits* b[8];
  for (int d = 0; d < 8; ++d)
    b[d] = &scan.rowBits(cb + glm::ivec3(d & 1, (d >> 1) & 1, (d >> 2) & 1));
  const auto row = [](const ActiveBrickScan::RowBits& own, const ActiveBrickScan::RowBits& next,
                      int at) {
    return std::uint16_t(own[std::size_t(at)] | ((next[std::size_t(at)] & 1u) << 8));
  };
#if defined(__SSE2__)
  const __m128i one = _mm_set1_epi8(1);
  const auto plane = [&](const std::uint8_t* own, const std::uint8_t* next, std::uint16_t* out) {
    const __m128i a = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(own));
    const __m128i n = _mm_and_si128(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(next)), one);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_unpacklo_epi8(a, n));  // rows y = 0..7
  };
  for (int z = 0; z < kBrickEdge; ++z)
    plane(b[0]->data() + kBrickEdge * z, b[1]->data() + kBrickEdge * z, rows.data() + kBlock * z);
  plane(b[4]->data(), b[5]->data(), rows.data() + kBlock * kBrickEdge);
#else
  for (int z = 0; z < kBrickEdge; ++z)
    for (int y = 0; y < kBrickEdge; ++y)
      rows[std::size_t(y + kBlock * z)] = row(*b[0], *b[1], y + kBrickEdge * z);
  for (int y = 0; y < kBrickEdge; ++y)
    rows[std::size_t(y + kBlock * kBrickEdge)] = row(*b[4], *b[5], y);
#endif
  for (int z = 0; z < kBrickEdge; ++z)
    rows[std::size_t(kBrickEdge + kBlock * z)] = row(*b[2], *b[3], kBrickEdge * z);  // y = 8
  rows[std::size_t(kBrickEdge + kBlock * kBrickEdge)] = row(*b[6], *b[7], 0);
}

// The eight rows of cells of layer lz at once: their mixed cells (corners not all inside or
// all outside) into mixed[ly], and, for the edges they own, the crossings and their prefix
// counts in vertex order (axis by axis, row by row), numbered on from `edges`. Returns the
// rows with a mixed cell as bits. A row without one has no crossed edge either (each edge
// a row's cells own lies on one of them). Rows and cells outside the grid are left out.
std::uint32_t classifyLayer(const RowMasks& rows, int lz, std::uint32_t cells, std::uint32_t rowsIn,
                            std::uint8_t* mixed, EdgeIndex& edgeIndex, std::uint32_t& edges) {
  const std::uint16_t* r = rows.data() + kBlock * lz;
  std::uint8_t* crossings = edgeIndex.crossings.data() + edgeByte(kBrickEdge * lz, 0);
  std::uint16_t* before = edgeIndex.crossingsBefore.data() + edgeByte(kBrickEdge * lz, 0);
#if defined(__SSE2__)
  // One 16-bit lane per row: its own inside bits (a), +y (b), +z (c), +y+z (d).
  const auto load = [](const std::uint16_t* p) {
    return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
  };
  const __m128i a = load(r), b = load(r + 1), c = load(r + kBlock), d = load(r + kBlock + 1);
  const __m128i laneBit = _mm_set_epi16(128, 64, 32, 16, 8, 4, 2, 1);
  const __m128i rowIn =
      _mm_cmpeq_epi16(_mm_and_si128(_mm_set1_epi16(std::int16_t(rowsIn)), laneBit), laneBit);
  const __m128i in = _mm_and_si128(_mm_set1_epi16(std::int16_t(cells)), rowIn);
  const __m128i any = _mm_or_si128(_mm_or_si128(a, b), _mm_or_si128(c, d));
  const __m128i all = _mm_and_si128(_mm_and_si128(a, b), _mm_and_si128(c, d));
  const __m128i mixedCells =
      _mm_and_si128(_mm_andnot_si128(_mm_and_si128(all, _mm_srli_epi16(all, 1)),
                                     _mm_or_si128(any, _mm_srli_epi16(any, 1))),
                    in);
  const __m128i zero = _mm_setzero_si128();
  const __m128i mixedBytes = _mm_packus_epi16(mixedCells, zero);
  _mm_storel_epi64(reinterpret_cast<__m128i*>(mixed), mixedBytes);
  const auto layerRows = std::uint32_t(~_mm_movemask_epi8(_mm_cmpeq_epi8(mixedBytes, zero)) & 0xff);
  if (layerRows == 0) return 0;
  const __m128i cx = _mm_and_si128(_mm_xor_si128(a, _mm_srli_epi16(a, 1)), in);
  const __m128i cy = _mm_and_si128(_mm_xor_si128(a, b), in);
  const __m128i cz = _mm_and_si128(_mm_xor_si128(a, c), in);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(crossings), _mm_packus_epi16(cx, cy));
  _mm_storel_epi64(reinterpret_cast<__m128i*>(crossings + 2 * kBrickEdge),
                   _mm_packus_epi16(cz, zero));
  // Set bits of each lane (at most eight).
  const auto bitCount8 = [](__m128i v) {
    v = _mm_sub_epi16(v, _mm_and_si128(_mm_srli_epi16(v, 1), _mm_set1_epi16(0x55)));
    v = _mm_add_epi16(_mm_and_si128(v, _mm_set1_epi16(0x33)),
                      _mm_and_si128(_mm_srli_epi16(v, 2), _mm_set1_epi16(0x33)));
    return _mm_and_si128(_mm_add_epi16(v, _mm_srli_epi16(v, 4)), _mm_set1_epi16(0x0f));
  };
  const __m128i nx = bitCount8(cx), ny = bitCount8(cy), nz = bitCount8(cz);
  const auto upTo = [](__m128i v) {  // inclusive prefix over rows
    v = _mm_add_epi16(v, _mm_slli_si128(v, 2));
    v = _mm_add_epi16(v, _mm_slli_si128(v, 4));
    return _mm_add_epi16(v, _mm_slli_si128(v, 8));
  };
  const auto total = [](__m128i prefix) {  // the last row's prefix (the layer's sum), in every lane
    const __m128i high = _mm_shufflehi_epi16(prefix, 0xff);
    return _mm_unpackhi_epi64(high, high);
  };
  const __m128i ux = upTo(nx), uy = upTo(ny), uz = upTo(nz);
  const __m128i firstX =
      _mm_set1_epi16(std::int16_t(edges));  // each axis's first id, in every lane
  const __m128i firstY = _mm_add_epi16(firstX, total(ux));
  const __m128i firstZ = _mm_add_epi16(firstY, total(uy));
  const __m128i beforeX = _mm_add_epi16(_mm_sub_epi16(ux, nx), firstX);
  const __m128i beforeY = _mm_add_epi16(_mm_sub_epi16(uy, ny), firstY);
  const __m128i beforeZ = _mm_add_epi16(_mm_sub_epi16(uz, nz), firstZ);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(before), beforeX);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(before + kBrickEdge), beforeY);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(before + 2 * kBrickEdge), beforeZ);
  edges +=
      std::uint32_t(_mm_extract_epi16(ux, 7) + _mm_extract_epi16(uy, 7) + _mm_extract_epi16(uz, 7));
  return layerRows;
#else
  std::uint32_t layerRows = 0;
  for (int ly = 0; ly < kBrickEdge; ++ly) {
    const std::uint32_t in = (rowsIn >> ly) & 1u ? cells : 0u;
    const std::uint32_t a = r[ly], b = r[ly + 1], c = r[ly + kBlock], d = r[ly + kBlock + 1];
    const std::uint32_t any = a | b | c | d, all = a & b & c & d;
    mixed[ly] = std::uint8_t(((any | (any >> 1)) & ~(all & (all >> 1))) & in);
    if (mixed[ly] != 0) layerRows |= 1u << ly;
  }
  if (layerRows == 0) return 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int ly = 0; ly < kBrickEdge; ++ly) {
      const std::uint32_t in = (rowsIn >> ly) & 1u ? cells : 0u;
      const std::uint32_t a = r[ly];
      const std::uint32_t far = axis == 0 ? a >> 1 : (axis == 1 ? r[ly + 1] : r[ly + kBlock]);
      const std::uint32_t crossing = (a ^ far) & in;
      crossings[kBrickEdge * axis + ly] = std::uint8_t(crossing);
      before[kBrickEdge * axis + ly] = std::uint16_t(edges);
      edges += kBitsInByte[crossing];
    }
  return layerRows;
#endif
}

}  // namespace

// Pass 1: inside bits, cases, counts. A dense block (nearly all) takes its inside bits from
// the scan; one at the grid's border reads and clips its fills.
void countBrick(const VoxelGrid& grid, const ActiveBrickScan& scan, const glm::ivec3& cb,
                bool shared, BrickOut& o, EdgeIndex& edgeIndex) {
  o.source.init(grid, cb);
  glm::ivec3 lo, hi;
  cellRange(grid, cb, lo, hi);
  const glm::ivec3 l0 = lo - cb * kBrickEdge;
  const glm::ivec3 l1 = hi - cb * kBrickEdge;
  RowMasks inside;
  if (o.source.dense) {
    insideRowsFromScan(scan, cb, inside);
  } else {
    insideRows(o.source, inside);
  }
  const std::uint32_t cells = xRange(l0.x, l1.x);   // cells in the grid along x, as bits
  const std::uint32_t rowsIn = xRange(l0.y, l1.y);  // and along y
  const auto& packed = packedCaseCounts();
  std::uint32_t edges = 0;
  std::uint64_t sums = 0;  // CaseCounts fields summed in 16-bit lanes (a brick's fit)
  std::uint64_t surfaceRows = 0, lastCellRows = 0;
  for (int lz = l0.z; lz < l1.z; ++lz) {
    std::uint8_t* mixed = o.mixed.data() + kBrickEdge * lz;
    const std::uint32_t layerRows =
        classifyLayer(inside, lz, cells, rowsIn, mixed, edgeIndex, edges);
    surfaceRows |= std::uint64_t(layerRows) << (kBrickEdge * lz);
#if defined(__SSE2__)
    const auto last =
        std::uint32_t(_mm_movemask_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(mixed)))) &
        0xffu;
#else
    std::uint32_t last = 0;
    for (int ly = 0; ly < kBrickEdge; ++ly) last |= std::uint32_t(mixed[ly] >> 7) << ly;
#endif
    lastCellRows |= std::uint64_t(last) << (kBrickEdge * lz);
    for (std::uint32_t rows = layerRows; rows != 0; rows &= rows - 1) {
      const int ly = __builtin_ctz(rows);
      std::uint32_t r[4];
      rowCorners(inside, ly, lz, r);
      std::uint64_t& configs = o.configs[std::size_t(ly + kBrickEdge * lz)];
      configs = rowConfigs(r);
      // All eight cells, without a branch per mixed one: a cell that is not mixed (or lies
      // outside the grid, all its corners outside) has case 0 or 255, which add nothing.
      const auto* c = reinterpret_cast<const std::uint8_t*>(&configs);
      sums += (packed[c[0]] + packed[c[1]]) + (packed[c[2]] + packed[c[3]]) +
              (packed[c[4]] + packed[c[5]]) + (packed[c[6]] + packed[c[7]]);
    }
  }
  const auto lane = [sums](int i) { return std::uint32_t((sums >> (16 * i)) & 0xffffu); };
  o.surfaceRows = surfaceRows;
  o.lastCellRows = lastCellRows;
  o.edges = shared ? edges : 0u;
  o.extras = lane(1) + (shared ? 0u : lane(3));
  o.triangles = lane(0);
  o.loopEntries = lane(2);
}

}  // namespace osteon::geometry::detail
