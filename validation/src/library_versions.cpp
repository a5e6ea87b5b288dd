#include "osteon/validation/library_versions.h"

#include <CGAL/version.h>
#include <OpenImageIO/imageio.h>

#include <string>

namespace osteon::validation {

geometry::LibraryVersions libraryVersions() {
  // openimageio_version(): 10000 major + 100 minor + patch.
  const int oiio = OIIO::openimageio_version();
  return {{"cgal", CGAL_VERSION_STR},
          {"openimageio", std::to_string(oiio / 10000) + "." + std::to_string(oiio / 100 % 100) + "." +
                              std::to_string(oiio % 100)}};
}

}  // namespace osteon::validation
