// osteon::image: images written through OpenImageIO without linking it. OpenImageIO's Debian
// build pulls in some 250 shared libraries (GDAL, FFmpeg, OpenCV, DCMTK, ...), which cost
// every process 0.1-0.5 s and ~120 MB at start. So OpenImageIO lives in a plugin,
// libosteon_image.so (image/plugin/), that this module loads with dlopen() the first time an
// image is written or OpenImageIO's version is asked for; a program that writes no image
// never loads it.
//
// Where the plugin is looked for, first found wins:
//   1. $OSTEON_IMAGE_PLUGIN, a path to the .so (when set, the only place tried);
//   2. the running executable's folder (/proc/self/exe);
//   3. the installed layout beside it: <exe folder>/../lib (CMAKE_INSTALL_LIBDIR relative to
//      CMAKE_INSTALL_BINDIR);
//   4. the build tree, where CMake builds the plugin;
//   5. the install prefix's library folder (CMAKE_INSTALL_FULL_LIBDIR);
//   6. the dynamic loader's own search (LD_LIBRARY_PATH, ld.so.cache).
#pragma once

#include <cstdint>
#include <string>

namespace osteon::image {

// Writes an 8-bit image, `height` rows of `width` x `channels` samples, top row first, to
// `path` in the format its extension names (.png, .tif, .jpg, ...). Returns an empty string
// on success, otherwise OpenImageIO's reason (one line); the caller names the file.
// Throws InputError (one line) when the plugin cannot be loaded.
[[nodiscard]] std::string writeImageU8(const std::string& path, int width, int height, int channels,
                                       const std::uint8_t* pixels);

// OpenImageIO's runtime version, "major.minor.patch"; loads the plugin. Throws InputError
// when it cannot be loaded.
std::string openImageIOVersion();

}  // namespace osteon::image
