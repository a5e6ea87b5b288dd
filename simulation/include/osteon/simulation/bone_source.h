// Opening a bone, the one way every front end does it (the CLI's commands, the viewer's command
// line, its File panel and file drops, the benches, the examples): a BoneSource says what to open
// and how, BoneModel::open(source) reads it and says what it was read as.
//
//   BoneSource source;
//   source.input = "humerus.stl";  source.units = "m";  source.voxelSizeMm = 0.6;
//   OpenedBone opened = BoneModel::open(source);   // opened.read.kind == "mesh"
//   Session session(opened.bone, SessionOptions{});
//
// Every check of a source is made here, once, with one message. The messages name the
// BoneSource field (OptionError "voxelSizeMm 0: must be a positive number of mm"); a front end
// names it as its users know it (commandLineMessage: "--voxel-size 0: ...").
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "osteon/core/error.h"
#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/volume_io.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/session.h"

namespace osteon::simulation {

struct BoneSource {
  // A mesh file (.stl .obj .ply .off), `default` (the built-in humerus), or a volume (.nrrd
  // .nhdr .nii .nii.gz: an osteon grid, a label map or a CT).
  std::string input = "default";
  // How a mesh's coordinates become millimetres: a unit (mm, cm, m, in), or a scale instead.
  std::string units = "mm";
  std::optional<double> scale;
  // A mesh's voxel edge. A volume has its own: when given, it must be the volume's, unless the
  // volume is resampled (anisotropic or oblique voxels), which then takes it.
  std::optional<double> voxelSizeMm;
  // A mesh without voxelSizeMm is voxelized at this; none: voxelSizeMm is required for a mesh.
  std::optional<double> defaultVoxelSizeMm;
  // What a volume means (its bone label, its iso level), which part is loaded (a crop) and how
  // it is read; label, iso and crops are refused for a mesh. Its voxelSizeMm is this source's.
  geometry::VolumeOptions volume;
  // A mesh's voxelization (rays, density rule); its voxel size and names come from the source.
  geometry::VoxelizeOptions voxelizing;
  // A mesh's level -2 fills, for refinement near the tool (sessions with levels 1 or 2).
  bool sampleFineFills = true;
  // The bone is for drilling sessions: refused when it holds no voxel inside, or when a session
  // on it would not fit in this machine's memory. false: read as it is (commands that report an
  // empty result).
  bool forSession = true;
  // Which way is up, from the shaft to the humeral head: x, y, z, -x, -y or -z in the bone's
  // own coordinates. Empty: found from the bone (its long axis, the end a sphere fits best).
  // Portal paths and exercises fit the head at that end.
  std::string up;

  bool isVolume() const { return geometry::isVolumePath(input); }
  bool isBuiltIn() const;
  // Millimetres per mesh coordinate (1 for a volume, whose header says its mm).
  double scaleToMm() const;
  // Every refusal that needs nothing read (scale, units, voxel size, volume options given for
  // a mesh), so a front end can refuse before any other work; open() makes it first too.
  void check() const;
  // The files it reads (none for `default`; a grid's density beside it): no output may
  // overwrite them.
  std::vector<std::string> inputFiles() const;
};

// What a source was read as.
struct BoneRead {
  std::string kind;                 // "mesh", or a volume's kind: "osteon grid", "label map", "ct"
  double scaleToMm = 1.0;           // mesh coordinates to mm, as used
  geometry::MeshFileInfo meshFile;  // mesh files: format, binary, faces triangulated or dropped
  std::optional<geometry::VolumeLoad> volume;  // volumes: what was found (its grid is the bone's)
  double loadMs = 0.0;  // the read (a volume's whole read, its density included)
};

struct OpenedBone {
  std::shared_ptr<const BoneModel> bone;
  BoneRead read;
};

// The mesh of a mesh source, read and scaled, not voxelized: for commands that work on the mesh
// itself (info, voxelize, check). Throws InputError for a volume.
struct BoneMesh {
  geometry::TriangleMesh mesh;
  BoneRead read;
};
BoneMesh loadBoneMesh(const BoneSource& source);

// The volume files BoneModel::open reads, as front ends list them in their help.
inline constexpr const char* kVolumeFormsText =
    ".nrrd .nhdr .nii .nii.gz .mha .mhd, a DICOM folder or .dcm file";

// A crop box as front ends take it, "X0:X1,Y0:Y1,Z0:Z1" in LPS mm (each range low below high).
// Throws OptionError "volume.cropMm <text>: <reason>".
geometry::BoxMm parseCropMm(const std::string& text);

// The command-line flag of a library option field ("voxelSizeMm" -> "--voxel-size"), as osteon's
// command lines (osteon, osteon-viewer) spell it; nullptr for a field they do not have.
const char* commandLineFlag(const std::string& field);
// e.what(), with an OptionError's field and every optionRef in it named by its flag.
std::string commandLineMessage(const InputError& e);

}  // namespace osteon::simulation
