#include "osteon/validation/library_versions.h"

#include <CGAL/version.h>

#include "osteon/image/image_writer.h"

namespace osteon::validation {

geometry::LibraryVersions libraryVersions() {
  // OpenImageIO's version is the plugin's runtime library's: asking loads the plugin.
  return {{"cgal", CGAL_VERSION_STR}, {"openimageio", image::openImageIOVersion()}};
}

}  // namespace osteon::validation
