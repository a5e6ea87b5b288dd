// libFuzzer: the NIfTI-1 volume loader (plain or gzip: zlib reads both), as
// `osteon mesh FILE.nii` reads it.
#include "fuzz_input.h"
#include "osteon/geometry/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return osteon::fuzz::runOnFile(
      data, size, ".nii", [](const std::string& path) { osteon::geometry::loadVolume(path); });
}
