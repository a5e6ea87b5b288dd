#include "support/files.h"

#include <algorithm>
#include <filesystem>

#include "osteon/core/error.h"

namespace osteon::cli {

namespace fs = std::filesystem;

RunFolder::RunFolder(const std::string& folder)
    : dir(folder, {"forces.csv", "summary.json", "surface.ply"}),
      forcesPath(folder + "/forces.csv"),
      summaryPath(folder + "/summary.json"),
      surfacePath(folder + "/surface.ply") {}

void refuseInputsInside(const std::string& folder, const std::vector<std::string>& inputs) {
  std::error_code ec;
  const fs::path dir = fs::weakly_canonical(folder, ec);
  if (ec) return;
  for (const std::string& in : inputs) {
    if (in.empty() || !fs::exists(in, ec)) continue;
    const fs::path file = fs::canonical(in, ec);
    if (ec) continue;
    const auto mismatch = std::mismatch(dir.begin(), dir.end(), file.begin(), file.end());
    if (mismatch.first == dir.end()) {
      throw InputError(in + ": is inside " + folder +
                       ", which this run fills with its own files "
                       "(refusing to risk overwriting an input; choose another --out-dir)");
    }
  }
}

}  // namespace osteon::cli
