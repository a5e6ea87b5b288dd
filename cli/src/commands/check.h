// `osteon check MESH`: the crack-free guarantees of one surface as numbers: exact checks (CGAL),
// the pixel crack metric, and with --reference its accuracy.
#pragma once

#include <string>

#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

struct CheckCommandOptions {
  simulation::BoneSource bone;  // the surface to check; its units are the reference's too
  std::string reference;        // empty: no accuracy
  int cracks = 512;             // pixels per side of each crack view
  std::string images;           // folder for the six crack views, empty for none
  bool json = false;
};

int runCheck(const CheckCommandOptions& options);

}  // namespace osteon::cli
