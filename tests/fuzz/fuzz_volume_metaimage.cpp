// libFuzzer: the MetaImage volume loader (.mha with attached data; raw or zlib), as
// `osteon mesh FILE.mha` reads it.
#include "fuzz_input.h"
#include "osteon/geometry/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return osteon::fuzz::runOnFile(
      data, size, ".mha", [](const std::string& path) { osteon::geometry::loadVolume(path); });
}
