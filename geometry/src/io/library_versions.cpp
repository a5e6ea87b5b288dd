#include "osteon/geometry/io/library_versions.h"

#include <string>

#include <OpenMesh/Core/System/config.h>
#include <embree3/rtcore_config.h>
#include <glm/detail/setup.hpp>
#include <tbb/version.h>

namespace osteon::geometry {

LibraryVersions libraryVersions() {
  // OM_VERSION packs major, minor and patch into one byte each: 0x90000 is 9.0.0.
  const int om = OM_VERSION;
  const std::string openMesh = std::to_string((om >> 16) & 0xff) + "." +
                               std::to_string((om >> 8) & 0xff) + "." + std::to_string(om & 0xff);
  return {
      {"embree", RTC_VERSION_STRING},
      {"openmesh", openMesh},
      {"tbb", TBB_runtime_version()},
      {"glm", std::to_string(GLM_VERSION_MAJOR) + "." + std::to_string(GLM_VERSION_MINOR) + "." +
                  std::to_string(GLM_VERSION_PATCH) + "." + std::to_string(GLM_VERSION_REVISION)}};
}

}  // namespace osteon::geometry
