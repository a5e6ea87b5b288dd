// OpenMesh's MeshIO must come before its other headers; it also registers the readers and
// writers we reach through IOManager.
#include "osteon/geometry/io/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include <OpenMesh/Core/IO/MeshIO.hh>

#include "openmesh_soup.h"
#include "osteon/core/error.h"
#include "osteon/core/input_file.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/geometry/io/units.h"
#include "preflight.h"

namespace osteon::geometry {

namespace fs = std::filesystem;

MeshFormat meshFormatFromPath(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".stl") return MeshFormat::Stl;
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".ply") return MeshFormat::Ply;
  if (ext == ".off") return MeshFormat::Off;
  throw InputError(path + ": unknown mesh extension '" + ext +
                   "' (expected .stl, .obj, .ply or .off)");
}

const char* meshFormatName(MeshFormat format) {
  switch (format) {
    case MeshFormat::Stl:
      return "stl";
    case MeshFormat::Obj:
      return "obj";
    case MeshFormat::Ply:
      return "ply";
    case MeshFormat::Off:
      return "off";
  }
  return "?";
}

namespace {

// OpenMesh's lower-case extension is how its IOManager picks a reader, whatever the case on
// disk; a temporary link is not worth it, so we hand it a stream and the extension instead.
std::string openMeshExtension(MeshFormat format) {
  return meshFormatName(format);
}

// OpenMesh's readers and writers chat on stdout/stderr; our errors are ours to report, and
// --json output must stay one clean object on stdout.
void silenceOpenMesh() {
  ::omlog().disable();
  ::omout().disable();
  ::omerr().disable();
}

std::string describeCoordinate(const glm::dvec3& p) {
  std::ostringstream s;
  s << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return s.str();
}

}  // namespace

void checkScaledCoordinates(const TriangleMesh& mesh, const std::string& name, double scaleToMm) {
  for (std::size_t v = 0; v < mesh.positionsMm.size(); ++v) {
    for (int a = 0; a < 3; ++a) {
      const double c = mesh.positionsMm[v][a];
      if (std::abs(c) <= kMaxCoordinateMm) continue;  // also false for NaN
      std::ostringstream s;
      s << name << ": vertex " << v << " coordinate " << c << " mm after scaling by " << scaleToMm
        << " is beyond +-1e9 mm (1000 km); check " << optionRef("units") << "/"
        << optionRef("scale");
      throw InputError(s.str());
    }
  }
}

TriangleMesh readMesh(const std::string& path, double scaleToMm, MeshFileInfo* info) {
  resolveScaleToMm("mm", scaleToMm);
  requireInputFile(path);
  std::error_code ec;
  const MeshFormat format = meshFormatFromPath(path);
  const std::uint64_t fileBytes = fs::file_size(path, ec);
  if (ec) throw InputError(path + ": cannot read its size (" + ec.message() + ")");
  if (fileBytes == 0) throw InputError(path + ": empty file");

  MeshFileInfo local;
  local.format = format;
  OpenMesh::IO::Options options;
  switch (format) {
    case MeshFormat::Stl:
      local.binary = detail::preflightStl(path, fileBytes) == detail::StlKind::Binary;
      if (local.binary) options += OpenMesh::IO::Options::Binary;
      break;
    case MeshFormat::Off:
      local.binary = detail::preflightOff(path, fileBytes);
      break;
    case MeshFormat::Ply:
      local.binary = detail::preflightPly(path, fileBytes);
      break;
    case MeshFormat::Obj:
      break;
  }
  if (format == MeshFormat::Stl && local.binary) detail::checkBinaryStlFinite(path);
  if (format == MeshFormat::Obj) detail::checkObj(path);
  if (format == MeshFormat::Stl && !local.binary) detail::checkAsciiStl(path);

  silenceOpenMesh();
  detail::SoupImporter importer(fileBytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  const bool ok = OpenMesh::IO::IOManager().read(in, openMeshExtension(format), importer, options);
  if (importer.error()) throw InputError(path + ": " + *importer.error());
  if (!ok)
    throw InputError(path + ": not a readable " + std::string(meshFormatName(format)) +
                     " file (the parser rejected it)");

  TriangleMesh mesh = importer.takeMesh();
  local.polygonsRead = importer.polygonsRead();
  local.polygonsTriangulated = importer.polygonsTriangulated();
  local.degenerateDropped = importer.degenerateDropped();
  if (mesh.positionsMm.empty()) throw InputError(path + ": empty mesh (no vertices)");
  if (mesh.triangles.empty()) {
    throw InputError(path + ": zero triangles (" + std::to_string(mesh.positionsMm.size()) +
                     " vertices, " + std::to_string(local.polygonsRead) + " faces)");
  }
  for (std::size_t v = 0; v < mesh.positionsMm.size(); ++v) {
    const glm::dvec3& p = mesh.positionsMm[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw InputError(path + ": vertex " + std::to_string(v) + " has a non-finite coordinate " +
                       describeCoordinate(p));
    }
  }
  if (scaleToMm != 1.0) scaleInPlace(mesh, scaleToMm);
  checkScaledCoordinates(mesh, path, scaleToMm);
  if (info) *info = local;
  return mesh;
}

void writeMesh(const TriangleMesh& mesh, const std::string& path, bool asciiStl) {
  const MeshFormat format = meshFormatFromPath(path);
  OpenMesh::IO::Options options;
  if (format == MeshFormat::Ply || (format == MeshFormat::Stl && !asciiStl)) {
    options += OpenMesh::IO::Options::Binary;
  }
  detail::SoupExporter exporter(mesh);
  silenceOpenMesh();
  OutputFile file(path);
  {
    std::ofstream out(file.tempPath(), std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot open for writing");
    const bool ok =
        OpenMesh::IO::IOManager().write(out, openMeshExtension(format), exporter, options, 17);
    out.close();
    if (!ok || !out) throw InputError(path + ": writing failed (disk full or not writable?)");
  }
  file.commit();
}

}  // namespace osteon::geometry
