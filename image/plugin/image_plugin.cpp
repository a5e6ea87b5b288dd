// libosteon_image.so: the image writer, the only osteon code that links OpenImageIO. Programs
// never link it; osteon::image loads it with dlopen() on the first image written (see
// src/image_writer.cpp), so commands that write no image do not load OpenImageIO's ~250
// shared libraries. Only the three functions of plugin_abi.h are exported.
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cstring>
#include <string>

#include "plugin_abi.h"

namespace {

void setError(char* errbuf, size_t errlen, std::string message) {
  if (errbuf == nullptr || errlen == 0) return;
  std::replace(message.begin(), message.end(), '\n', ' ');
  while (!message.empty() && message.back() == ' ') message.pop_back();
  const size_t n = std::min(message.size(), errlen - 1);
  std::memcpy(errbuf, message.data(), n);
  errbuf[n] = '\0';
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) int osteon_image_abi(void) {
  return OSTEON_IMAGE_ABI;
}

__attribute__((visibility("default"))) const char* osteon_image_library_version(void) {
  // openimageio_version(): 10000 major + 100 minor + patch.
  static const std::string version = [] {
    const int v = OIIO::openimageio_version();
    return std::to_string(v / 10000) + "." + std::to_string(v / 100 % 100) + "." +
           std::to_string(v % 100);
  }();
  return version.c_str();
}

__attribute__((visibility("default"))) int osteon_image_write_u8(const char* path, int width,
                                                                 int height, int channels,
                                                                 const unsigned char* pixels,
                                                                 char* errbuf, size_t errlen) {
  try {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
      setError(errbuf, errlen, "no writer for this file type (" + OIIO::geterror() + ")");
      return 1;
    }
    const OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, pixels) ||
        !out->close()) {
      setError(errbuf, errlen, out->geterror());
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {  // never let an exception cross the C boundary
    setError(errbuf, errlen, e.what());
    return 1;
  }
}

}  // extern "C"
