// libFuzzer: the .stl mesh loader (preflight, then OpenMesh), as `osteon info FILE.stl` reads it.
#include "fuzz_input.h"
#include "osteon/geometry/io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return osteon::fuzz::runOnFile(data, size, ".stl",
                                 [](const std::string& path) { osteon::geometry::readMesh(path); });
}
