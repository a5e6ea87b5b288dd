// `osteon model`: the built-in proximal humerus (what `default` means), optionally written.
#pragma once

#include <string>

namespace osteon::cli {

struct ModelOptions {
  std::string out;  // mesh file to write, empty for none
  bool json = false;
};

int runModel(const ModelOptions& options);

}  // namespace osteon::cli
