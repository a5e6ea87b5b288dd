// BoneModel::open and the BoneSource checks: the one way a bone is opened (bone_source.h).
#include "osteon/simulation/bone_source.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <utility>

#include "osteon/core/number_text.h"
#include "osteon/core/option_error.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/io/mesh_source.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/io/units.h"

namespace osteon::simulation {

namespace {

void requirePositiveMm(const char* field, const std::optional<double>& mm) {
  if (mm && !(std::isfinite(*mm) && *mm > 0.0))
    throw OptionError(field, numberText(*mm), "must be a positive number of mm");
}

// A volume's voxel edge is its own: a voxel size given with it must agree (to rounding).
void checkVolumeVoxelSize(const BoneSource& source, double volumeVoxelMm) {
  if (!source.voxelSizeMm) return;
  const double given = *source.voxelSizeMm;
  if (std::abs(given - volumeVoxelMm) <= 1e-6 * given) return;
  throw OptionError("voxelSizeMm", numberText(given),
                    source.input + " has voxels of " + numberText(volumeVoxelMm) +
                        " mm (a volume has its own voxel size: give that, or none where the voxel "
                        "size is optional)");
}

}  // namespace

bool BoneSource::isBuiltIn() const {
  return input == geometry::kDefaultModelArgument;
}

double BoneSource::scaleToMm() const {
  return isVolume() ? 1.0 : geometry::resolveScaleToMm(units, scale);
}

void BoneSource::check() const {
  requirePositiveMm("voxelSizeMm", voxelSizeMm);
  requirePositiveMm("defaultVoxelSizeMm", defaultVoxelSizeMm);
  if (!up.empty()) parseUpAxis(up);
  if (isVolume()) return;
  scaleToMm();
  const char* volumeOnly = volume.label         ? "volume.label"
                           : volume.isoValue    ? "volume.isoValue"
                           : volume.cropMm      ? "volume.cropMm"
                           : volume.cropToLabel ? "volume.cropToLabel"
                                                : nullptr;
  if (volumeOnly) {
    throw OptionError(volumeOnly, "",
                      "only for a volume (.nrrd, .nhdr, .nii, .nii.gz, .mha, .mhd, DICOM); " +
                          input + " is a mesh");
  }
  if (!volume.series.empty()) {
    throw OptionError("volume.series", volume.series,
                      "only for a DICOM volume (a folder or .dcm); " + input + " is a mesh");
  }
}

std::vector<std::string> BoneSource::inputFiles() const {
  if (isBuiltIn()) return {};
  if (isVolume() && geometry::densityPathFor(input) != input)
    return {input, geometry::densityPathFor(input)};
  return {input};
}

BoneMesh loadBoneMesh(const BoneSource& source) {
  source.check();
  BoneMesh out;
  out.read.kind = "mesh";
  out.read.scaleToMm = source.scaleToMm();
  const Clock::time_point start = Clock::now();
  out.mesh = geometry::loadMeshArgument(source.input, out.read.scaleToMm, &out.read.meshFile);
  out.read.loadMs = msSince(start);
  return out;
}

OpenedBone BoneModel::open(const BoneSource& source) {
  const Clock::time_point start = Clock::now();
  source.check();
  OpenedBone out;
  if (source.isVolume()) {
    // A resampled volume (anisotropic or oblique voxels) takes the source's voxel size.
    geometry::VolumeOptions volume = source.volume;
    volume.voxelSizeMm = source.voxelSizeMm;
    geometry::VolumeLoad load = geometry::loadVolume(source.input, volume);
    out.read.loadMs = msSince(start);
    checkVolumeVoxelSize(source, load.grid.voxelSizeMm());
    out.read.kind = load.kind;
    std::shared_ptr<BoneModel> bone = wrapGrid(std::move(load.grid), source.input, out.read.loadMs);
    if (source.forSession && bone->grid_.countVoxels(geometry::kFillHalf) == 0) {
      throw InputError(source.input + ": the grid has no voxel inside (nothing to drill)");
    }
    out.read.volume = std::move(load);
    if (!source.up.empty()) bone->up_ = parseUpAxis(source.up);
    out.bone = std::move(bone);
    return out;
  }
  if (!source.voxelSizeMm && !source.defaultVoxelSizeMm) {
    throw OptionError("voxelSizeMm", "", "required when the input is a mesh");
  }
  BoneMesh mesh = loadBoneMesh(source);
  out.read = std::move(mesh.read);
  geometry::VoxelizeOptions voxelizing = source.voxelizing;
  voxelizing.voxelSizeGiven = source.voxelSizeMm.has_value() && source.voxelizing.voxelSizeGiven;
  std::shared_ptr<BoneModel> bone = build(
      std::move(mesh.mesh), source.voxelSizeMm.value_or(source.defaultVoxelSizeMm.value_or(0.0)),
      source.input, out.read.scaleToMm, voxelizing, source.sampleFineFills, source.forSession);
  bone->setup_.loadMs = out.read.loadMs;
  bone->setup_.totalMs = msSince(start);
  if (!source.up.empty()) bone->up_ = parseUpAxis(source.up);
  out.bone = std::move(bone);
  return out;
}

geometry::BoxMm parseCropMm(const std::string& text) {
  const auto bad = [&text](const std::string& why) {
    return OptionError("volume.cropMm", text, why);
  };
  std::vector<std::string> ranges;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');) ranges.push_back(part);
  if (ranges.size() != 3) throw bad("needs three ranges X0:X1,Y0:Y1,Z0:Z1 (mm)");
  const auto number = [](const std::string& t, double& v) {
    char* end = nullptr;
    v = std::strtod(t.c_str(), &end);
    return !t.empty() && end == t.c_str() + t.size() && std::isfinite(v);
  };
  geometry::BoxMm box;
  for (int a = 0; a < 3; ++a) {
    const std::string& r = ranges[std::size_t(a)];
    const std::size_t colon = r.find(':');
    double lo = 0.0, hi = 0.0;
    if (colon == std::string::npos || !number(r.substr(0, colon), lo) ||
        !number(r.substr(colon + 1), hi) || !(lo < hi)) {
      throw bad(std::string("range ") + "XYZ"[a] + " '" + r +
                "' is not LOW:HIGH (finite mm, low below high)");
    }
    box.minMm[a] = lo;
    box.maxMm[a] = hi;
  }
  return box;
}

const char* commandLineFlag(const std::string& field) {
  static const std::pair<const char*, const char*> kFlags[] = {
      {"scale", "--scale"},
      {"units", "--units"},
      {"voxelSizeMm", "--voxel-size"},
      {"volume.label", "--label"},
      {"volume.isoValue", "--iso"},
      {"volume.voxelSizeMm", "--voxel-size"},
      {"volume.cropMm", "--crop"},
      {"volume.cropToLabel", "--crop-to-label"},
      {"volume.cropMarginMm", "--crop-margin"},
      {"volume.allowOutsideData", "--allow-outside-data"},
      {"levels", "--levels"},
      {"forceModel", "--force-model"},
      {"drill.rpm", "--rpm"},
      {"tool", "--tool"},
      {"xi", "--xi"},
      {"raysPerAxis", "--rays"},
      {"corticalThicknessMm", "--cortical-mm"},
      {"smoothIterations", "--smooth"},
      {"up", "--up"},
      {"coupling", "--coupling"},
      {"path", "--path"},
      {"crackPixels", "--cracks"},
      {"volume.series", "--series"},
      {"igtl.port", "--igtl"},
      {"igtl.bind", "--igtl-bind"},
      {"igtl.content", "--igtl-content"},
      {"outDir", "--out-dir"}};
  for (const auto& [name, flag] : kFlags) {
    if (field == name) return flag;
  }
  return nullptr;
}

std::string commandLineMessage(const InputError& e) {
  return renderOptions(e.marked(), [](const std::string& field) { return commandLineFlag(field); });
}

}  // namespace osteon::simulation
