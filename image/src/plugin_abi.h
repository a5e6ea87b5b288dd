// The C interface between osteon::image (the loader, linked into programs) and the
// libosteon_image.so plugin (the only code that links OpenImageIO). Plain C types only, so
// the two sides need not agree on a C++ ABI; bump OSTEON_IMAGE_ABI on any change here.
#pragma once

#include <stddef.h>

#define OSTEON_IMAGE_ABI 1

#ifdef __cplusplus
extern "C" {
#endif

// OSTEON_IMAGE_ABI of the plugin: the loader refuses a plugin built for another interface.
typedef int (*osteon_image_abi_fn)(void);

// OpenImageIO's runtime version as "major.minor.patch" (static storage).
typedef const char* (*osteon_image_library_version_fn)(void);

// Writes `pixels` (height rows of width x channels 8-bit samples, top row first) to `path`,
// in the format its extension names. 0 on success; otherwise non-zero, with OpenImageIO's
// reason in errbuf (one line, truncated to errlen - 1 characters).
typedef int (*osteon_image_write_u8_fn)(const char* path, int width, int height, int channels,
                                        const unsigned char* pixels, char* errbuf, size_t errlen);

// The plugin's exported symbols, looked up by these names.
int osteon_image_abi(void);
const char* osteon_image_library_version(void);
int osteon_image_write_u8(const char* path, int width, int height, int channels,
                          const unsigned char* pixels, char* errbuf, size_t errlen);

#ifdef __cplusplus
}
#endif
