// libFuzzer: the NRRD volume loader (osteon grids, label maps, CTs; raw and gzip), as
// `osteon mesh FILE.nrrd` reads it.
#include "fuzz_input.h"
#include "osteon/geometry/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return osteon::fuzz::runOnFile(
      data, size, ".nrrd", [](const std::string& path) { osteon::geometry::loadVolume(path); });
}
