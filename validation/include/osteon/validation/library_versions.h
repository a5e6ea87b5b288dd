// The versions of the libraries the validation module is built with (CGAL, OpenImageIO), so
// their headers stay inside this module. CGAL is header-only: its version is the headers'.
// OpenImageIO's is the runtime library's own, asked of the osteon::image plugin: calling this
// loads the plugin (and OpenImageIO) if no image was written yet, and throws InputError when it
// cannot be loaded. Commands that write no image should not call it.
#pragma once

#include "osteon/geometry/io/library_versions.h"

namespace osteon::validation {

geometry::LibraryVersions libraryVersions();

}  // namespace osteon::validation
