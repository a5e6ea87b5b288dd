// The DICOM plugin's image reading (dicom_plugin.cpp) and a series' decoding (dicom_decode.cpp):
// one file read as an image after the checks that keep GDCM from asserting, its pixels decoded.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

#include "dicom_plugin_abi.h"
#include "dicom_series.h"

namespace gdcm {
class File;
class Image;
class ImageReader;
}  // namespace gdcm

namespace osteon::dicom {

struct Pixels {
  const char* type = nullptr;
  std::size_t bytes = 0;
  bool isSigned = false;
  int bitsStored = 0, bitsAllocated = 0;
};

// One grey sample per pixel, of an integer type osteon stores; refused otherwise.
Pixels pixelsOf(const gdcm::Image& image, const std::string& file);

// Bits above BitsStored may hold overlays or garbage: masked, or the sign carried into them.
template <typename T>
void keepStoredBits(char* data, std::size_t count, const Pixels& p) {
  if (p.bitsStored <= 0 || p.bitsStored >= int(8 * sizeof(T))) return;
  using U = std::make_unsigned_t<T>;
  const U mask = U((U(1) << p.bitsStored) - 1), sign = U(U(1) << (p.bitsStored - 1));
  for (std::size_t i = 0; i < count; ++i) {
    U u;
    std::memcpy(&u, data + i * sizeof(T), sizeof(T));
    u = U(u & mask);
    if (p.isSigned && (u & sign)) u = U(u | U(~mask));
    std::memcpy(data + i * sizeof(T), &u, sizeof(T));
  }
}

// `file` read as an image by `reader`, after the checks of what GDCM would assert on.
void readImage(gdcm::ImageReader& reader, const std::string& file);

// The pixel data must be able to hold the image its header describes (`bytes`), checked before
// the values are allocated.
void refuseImplausible(const gdcm::File& f, const std::string& file, std::uint64_t bytes);

// Decodes one image's pixels into `to` (exactly `bytes`).
void decode(const gdcm::Image& image, const std::string& file, char* to, std::size_t bytes);

// Where the plugin's values go, and who hears of its progress (dicom_plugin_abi.h).
struct Output {
  osteon_dicom_volume* volume;
  osteon_dicom_alloc_fn alloc;
  osteon_dicom_progress_fn progress;
  void* context;
  char* allocate(std::size_t bytes) const {
    void* p = alloc(context, bytes);
    if (!p) throw Failure{3, "no memory for the volume"};
    return static_cast<char*>(p);
  }
  void tick(unsigned long long nextPixels = 0) const {
    if (progress) progress(context, nextPixels);
  }
};

// A stack of one-frame slices decoded into one volume, slices in parallel.
void readSeries(const Stack& stack, const Output& out);

}  // namespace osteon::dicom
