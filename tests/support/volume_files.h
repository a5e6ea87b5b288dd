// Small volumes as other tools write them (NRRD attached/detached, raw/gzip; NIfTI-1 .nii and
// .nii.gz), for tests that read them back through osteon's volume loader.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>
#include <zlib.h>

#include <glm/glm.hpp>

#include "support/files.h"

namespace osteon::test {

// Values x fastest, then y, then z.
struct TestVolume {
  glm::ivec3 sizes{1};
  double spacingMm = 1.0;
  glm::dvec3 firstCentreMm{0.0};  // centre of voxel (0,0,0), LPS
  std::vector<double> values;
};

// Little-endian bytes of each value as `T`.
template <typename T>
std::string encodeAs(const std::vector<double>& values) {
  std::string bytes(values.size() * sizeof(T), '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    const T v = static_cast<T>(values[i]);
    std::memcpy(&bytes[i * sizeof(T)], &v, sizeof(T));  // test hosts are little-endian
  }
  return bytes;
}

inline std::string gzipBytes(const std::string& data) {
  z_stream z{};
  if (deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("deflate");
  std::string out(deflateBound(&z, uLong(data.size())) + 64, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  z.avail_in = uInt(data.size());
  z.next_out = reinterpret_cast<Bytef*>(&out[0]);
  z.avail_out = uInt(out.size());
  if (deflate(&z, Z_FINISH) != Z_STREAM_END) throw std::runtime_error("deflate");
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

// nrrdType: "short", "uint8", "float", ...; bytes: the values already encoded.
// dataFile: empty for an attached header, else the detached data's file name (beside `path`).
// directions: the "space directions" text; empty for the isotropic default.
inline void writeTestNrrd(const std::string& path, const TestVolume& v, const std::string& nrrdType,
                          const std::string& bytes, bool gzip, const std::string& dataFile = "",
                          const std::string& directions = "") {
  const std::string s = std::to_string(v.spacingMm);
  std::string h = "NRRD0004\n# written by a test, as 3D Slicer would\n";
  h += "type: " + nrrdType + "\ndimension: 3\nspace: left-posterior-superior\n";
  h += "sizes: " + std::to_string(v.sizes.x) + " " + std::to_string(v.sizes.y) + " " +
       std::to_string(v.sizes.z) + "\n";
  h += "space directions: " +
       (directions.empty() ? "(" + s + ",0,0) (0," + s + ",0) (0,0," + s + ")" : directions) + "\n";
  h += "kinds: domain domain domain\nendian: little\n";
  h += std::string("encoding: ") + (gzip ? "gzip" : "raw") + "\n";
  h += "space origin: (" + std::to_string(v.firstCentreMm.x) + "," +
       std::to_string(v.firstCentreMm.y) + "," + std::to_string(v.firstCentreMm.z) + ")\n";
  const std::string data = gzip ? gzipBytes(bytes) : bytes;
  if (dataFile.empty()) {
    writeBytes(path, h + "\n" + data);
  } else {
    writeBytes(path, h + "data file: " + dataFile + "\n");
    const std::string dir = path.substr(0, path.find_last_of('/') + 1);
    writeBytes(dir + dataFile, data);
  }
}

// MetaImage with its data attached (.mha), axis-aligned LPS; elementType "MET_SHORT", ...
inline void writeTestMetaImage(const std::string& path, const TestVolume& v,
                               const std::string& elementType, const std::string& bytes) {
  const std::string s = std::to_string(v.spacingMm);
  const std::string h =
      "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
      "TransformMatrix = 1 0 0 0 1 0 0 0 1\nOffset = " +
      std::to_string(v.firstCentreMm.x) + " " + std::to_string(v.firstCentreMm.y) + " " +
      std::to_string(v.firstCentreMm.z) + "\nAnatomicalOrientation = RAI\nElementSpacing = " + s +
      " " + s + " " + s + "\nDimSize = " + std::to_string(v.sizes.x) + " " +
      std::to_string(v.sizes.y) + " " + std::to_string(v.sizes.z) +
      "\nElementType = " + elementType + "\nElementDataFile = LOCAL\n";
  writeBytes(path, h + bytes);
}

// NIfTI-1 single file; datatype 2 uint8, 4 int16, 16 float, ... `.nii.gz` when gz. The sform
// is RAS, as NIfTI defines: LPS x and y are negated.
inline void writeTestNifti(const std::string& path, const TestVolume& v, std::int16_t datatype,
                           std::int16_t bitpix, const std::string& bytes, bool gz) {
  unsigned char h[352] = {};
  const auto put = [&h](std::size_t offset, const auto value) {
    std::memcpy(h + offset, &value, sizeof(value));
  };
  put(0, std::int32_t(348));
  put(40, std::int16_t(3));
  put(42, std::int16_t(v.sizes.x));
  put(44, std::int16_t(v.sizes.y));
  put(46, std::int16_t(v.sizes.z));
  put(48, std::int16_t(1));
  put(70, datatype);
  put(72, bitpix);
  put(76, float(1));
  put(80, float(v.spacingMm));
  put(84, float(v.spacingMm));
  put(88, float(v.spacingMm));
  put(108, float(352));
  put(112, float(0));         // scl_slope 0: no scaling
  put(254, std::int16_t(1));  // sform_code
  const double ras[3][4] = {{-v.spacingMm, 0, 0, -v.firstCentreMm.x},
                            {0, -v.spacingMm, 0, -v.firstCentreMm.y},
                            {0, 0, v.spacingMm, v.firstCentreMm.z}};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) put(std::size_t(280 + 16 * r + 4 * c), float(ras[r][c]));
  }
  std::memcpy(h + 344, "n+1\0", 4);
  const std::string file = std::string(reinterpret_cast<const char*>(h), 352) + bytes;
  writeBytes(path, gz ? gzipBytes(file) : file);
}

}  // namespace osteon::test
