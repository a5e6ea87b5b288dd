// libFuzzer: the .obj mesh loader (preflight, then OpenMesh), as `osteon info FILE.obj` reads it.
#include "fuzz_input.h"
#include "osteon/geometry/io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return osteon::fuzz::runOnFile(data, size, ".obj",
                                 [](const std::string& path) { osteon::geometry::readMesh(path); });
}
