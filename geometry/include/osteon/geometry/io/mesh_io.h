// Mesh files in and out: STL (ASCII and binary), OBJ, PLY, OFF, parsed by OpenMesh into a
// lossless triangle soup (polygons fan-triangulated). Every failure is an InputError whose
// one-line message names the file and the reason.
#pragma once

#include <cstddef>
#include <string>

#include "osteon/geometry/io/mesh.h"

namespace osteon::geometry {

enum class MeshFormat { Stl, Obj, Ply, Off };

// Format from the file extension (case-insensitive); throws InputError for any other.
MeshFormat meshFormatFromPath(const std::string& path);
const char* meshFormatName(MeshFormat format);

struct MeshFileInfo {
  MeshFormat format = MeshFormat::Stl;
  bool binary = false;                   // binary STL or PLY
  std::size_t polygonsRead = 0;          // faces as stored in the file
  std::size_t polygonsTriangulated = 0;  // faces with more than three corners
  std::size_t degenerateDropped = 0;     // faces that repeat a corner (no area, no topology)
};

// Coordinates beyond +-1e9 mm (1000 km) are a units mistake: no bone is that large, and volume
// and voxel arithmetic would overflow.
inline constexpr double kMaxCoordinateMm = 1e9;

// Throws InputError "<name>: vertex V coordinate C mm after scaling by S is beyond +-1e9 mm
// (1000 km); check --units/--scale" for the first coordinate that is not finite or beyond
// kMaxCoordinateMm.
void checkScaledCoordinates(const TriangleMesh& mesh, const std::string& name, double scaleToMm);

// Reads a mesh and multiplies positions by scaleToMm (1 for files in millimetres).
// Throws InputError for: a missing or unreadable file, an unknown extension, an empty mesh,
// zero triangles, NaN or Inf coordinates (also after scaling, or beyond kMaxCoordinateMm),
// malformed text records (errors name the line), a truncated binary STL, a binary STL triangle
// count that overflows 32-bit size arithmetic, face indices out of range, and headers that promise
// more data than the file holds.
TriangleMesh readMesh(const std::string& path, double scaleToMm = 1.0,
                      MeshFileInfo* info = nullptr);

// Writes by extension: STL binary (or ASCII with asciiStl), PLY binary, OBJ and OFF text with
// round-trip precision. Throws InputError when the file cannot be written.
void writeMesh(const TriangleMesh& mesh, const std::string& path, bool asciiStl = false);

}  // namespace osteon::geometry
