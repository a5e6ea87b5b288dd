// `osteon info MESH`: a mesh's size, bounds, volume and topology.
#pragma once

#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

struct InfoOptions {
  simulation::BoneSource bone;  // a mesh, `default` or a volume; units, volume meaning
  bool json = false;
};

int runInfo(const InfoOptions& options);

}  // namespace osteon::cli
