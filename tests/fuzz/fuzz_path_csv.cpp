// libFuzzer: the drill-path CSV parser, as `osteon drill MESH --path FILE.csv` reads it.
#include "fuzz_input.h"
#include "osteon/simulation/path.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return osteon::fuzz::runOnFile(
      data, size, ".csv", [](const std::string& path) { osteon::simulation::loadPathCsv(path); });
}
