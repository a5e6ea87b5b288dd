// libFuzzer: the DICOM volume loader and its GDCM plugin, as `osteon mesh FILE.dcm` reads it.
// The file lies alone in a folder of its own: a one-frame slice stands for its series in its
// folder, which must not be the RAM disk other fuzzers write to.
#include <cerrno>
#include <sys/stat.h>

#include "fuzz_input.h"
#include "osteon/geometry/io/volume_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool folder = [] {
    const std::string& path = osteon::fuzz::inputPath("_dicom/slice.dcm");
    return ::mkdir(path.substr(0, path.rfind('/')).c_str(), 0700) == 0 || errno == EEXIST;
  }();
  if (!folder) std::abort();
  return osteon::fuzz::runOnFile(data, size, "_dicom/slice.dcm", [](const std::string& path) {
    osteon::geometry::loadVolume(path);
  });
}
