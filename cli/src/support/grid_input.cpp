#include "support/grid_input.h"

#include "support/volume_report.h"

namespace osteon::cli {

LoadedGrid loadGrid(simulation::BoneSource source) {
  LoadedGrid out;
  source.forSession = false;
  source.sampleFineFills = false;
  simulation::OpenedBone opened = simulation::BoneModel::open(source);
  out.bone = std::move(opened.bone);
  out.setup = out.bone->setupTimings();
  out.voxelizeMs = out.setup.voxelizeMs + out.setup.densityMs;
  if (opened.read.volume) {
    out.volume = volumeJson(*opened.read.volume, source.volume);
    out.volumeText = volumeLine(*opened.read.volume, source.volume);
  }
  return out;
}

}  // namespace osteon::cli
