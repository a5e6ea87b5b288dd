// Mesh files in and out: STL (ASCII and binary), OBJ, PLY, OFF, parsed by OpenMesh into a
// lossless triangle soup (polygons fan-triangulated). Every failure is an InputError whose
// one-line message names the file and the reason.
#pragma once

#include "osteon/geometry/mesh.h"

#include <cstddef>
#include <string>

namespace osteon::geometry {

enum class MeshFormat { Stl, Obj, Ply, Off };

// Format from the file extension (case-insensitive); throws InputError for any other.
MeshFormat meshFormatFromPath(const std::string& path);
const char* meshFormatName(MeshFormat format);

struct MeshFileInfo {
  MeshFormat format = MeshFormat::Stl;
  bool binary = false;                  // binary STL or PLY
  std::size_t polygonsRead = 0;         // faces as stored in the file
  std::size_t polygonsTriangulated = 0;  // faces with more than three corners
  std::size_t degenerateDropped = 0;    // faces that repeat a corner (no area, no topology)
};

// Reads a mesh and multiplies positions by scaleToMm (1 for files in millimetres).
// Throws InputError for: a missing or unreadable file, an unknown extension, an empty mesh,
// zero triangles, NaN or Inf coordinates, a truncated binary STL, a binary STL triangle count
// that overflows 32-bit size arithmetic, face indices out of range, and headers that promise
// more data than the file holds.
TriangleMesh readMesh(const std::string& path, double scaleToMm = 1.0,
                      MeshFileInfo* info = nullptr);

// Writes by extension: STL binary (or ASCII with asciiStl), PLY binary, OBJ and OFF text with
// round-trip precision. Throws InputError when the file cannot be written.
void writeMesh(const TriangleMesh& mesh, const std::string& path, bool asciiStl = false);

}  // namespace osteon::geometry
