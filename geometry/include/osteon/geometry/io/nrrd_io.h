// Voxel grids as NRRD files that 3D Slicer, ITK and VTK open with the right spacing and
// origin: fill in GRID.nrrd (uint8 0..255 when every fill is on the voxelizer's 1/255 steps,
// otherwise uint16 fill units 0..16320), density as int16 in a second file beside it
// (GRID.density.nrrd). Space is left-posterior-superior in millimetres, the frame osteon
// uses; "space origin" is the centre of voxel (0, 0, 0), as NRRD defines it for cell data.
#pragma once

#include <string>

#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

// GRID.nrrd -> GRID.density.nrrd (also for names without the .nrrd extension).
std::string densityPathFor(const std::string& fillPath);

// Writes fill (and, with withDensity, density beside it) raw little-endian, attached header,
// x fastest then y then z, plus osteon's keys (osteon_voxel_size_mm, osteon_origin_mm, %.17g)
// so the round trip is exact to the last bit. Without withDensity a stale density file beside
// fillPath is removed, so a later read does not pair the new fill with old density.
// Throws InputError when a file cannot be written.
void writeNrrd(const VoxelGrid& grid, const std::string& fillPath, bool withDensity = true);

// Reads GRID.nrrd (fill as uint8 steps or uint16 units, raw encoding) and, when it exists,
// GRID.density.nrrd (int16, either byte order). Without a density file, density is left 0 for the
// caller's rule. Voxel size and origin come from osteon's keys when present (they must agree with
// the standard fields), otherwise from "space directions" + "space origin" or "spacings". Bricks
// whose voxels all agree stay uniform; the result has no dirty bricks. The header is read as every
// NRRD osteon opens (src/io/nrrd_header.h): the data may be attached or in a `data file:` inside
// the header's folder (anywhere with allowOutsideData), after `line skip:` lines and `byte skip:`
// bytes. Throws InputError "<file>: <reason>" for anything it cannot honour: a missing file, magic
// or field, a field given twice, a non-spatial kind, a fill type other than uint8/uint16 or a
// density type other than int16, a dimension other than 3, gzip or other non-raw encodings, a
// space other than LPS, non-axis-aligned or non-isotropic
// spacing, a voxel size that is not positive and finite, an origin or far corner beyond
// +-1e9 mm (kMaxCoordinateMm), a header line longer than 64 KiB (named by its number), more
// than 2^32 voxels, data shorter or longer than the sizes say (checked before anything is
// read or allocated), a density file whose sizes or geometry differ from the fill's.
struct NrrdReadResult {
  VoxelGrid grid;
  bool densityLoaded = false;
};
NrrdReadResult readNrrd(const std::string& fillPath, bool allowOutsideData = false);

}  // namespace osteon::geometry
