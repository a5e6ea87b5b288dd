// NIfTI-1 volumes (.nii, .nii.gz; volume_io.h): the 348-byte header, its sform, qform or pixdim
// geometry turned from RAS to LPS, and the data, handed to placeVolume like every reader's.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <zlib.h>

#include "io/nrrd_header.h"
#include "io/volume_place.h"
#include "osteon/core/error.h"
#include "osteon/core/input_file.h"
#include "osteon/core/number_text.h"

namespace osteon::geometry {

namespace fs = std::filesystem;

namespace {

using nrrd::Scalar;

template <typename T>
T at(const unsigned char* h, std::size_t offset, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, h + offset, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

struct NiftiHeader {
  std::string path;
  unsigned char bytes[352];
  bool swap = false;
  template <typename T>
  T get(std::size_t offset) const {
    return at<T>(bytes, offset, swap);
  }
  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(path + ": " + reason);
  }
};

Scalar scalarOf(const NiftiHeader& h) {
  const int datatype = h.get<std::int16_t>(70);
  Scalar s;
  switch (datatype) {
    case 2:
      s = {"uint8", 1, true, false};
      break;
    case 4:
      s = {"int16", 2, true, true};
      break;
    case 8:
      s = {"int32", 4, true, true};
      break;
    case 16:
      s = {"float", 4, false, true};
      break;
    case 64:
      s = {"double", 8, false, true};
      break;
    case 256:
      s = {"int8", 1, true, true};
      break;
    case 512:
      s = {"uint16", 2, true, false};
      break;
    case 768:
      s = {"uint32", 4, true, false};
      break;
    case 1024:
      s = {"int64", 8, true, true};
      break;
    case 1280:
      s = {"uint64", 8, true, false};
      break;
    default:
      h.fail("datatype " + std::to_string(datatype) + " is not a supported scalar type");
  }
  // bitpix must say the datatype's width: a header that disagrees with itself is not trusted.
  const int bitpix = h.get<std::int16_t>(72);
  if (bitpix != int(8 * s.bytes)) {
    h.fail("bitpix " + std::to_string(bitpix) + " does not match datatype " +
           std::to_string(datatype) + " (" + s.name + ", " + std::to_string(8 * s.bytes) +
           " bits)");
  }
  return s;
}

// The qform: a unit quaternion (b, c, d), pixdim and qfac, and an offset.
void qformAffine(const NiftiHeader& h, double m[3][3], glm::dvec3& centre0) {
  double b = h.get<float>(256), c = h.get<float>(260), d = h.get<float>(264);
  const glm::dvec3 offset(h.get<float>(268), h.get<float>(272), h.get<float>(276));
  const double qfac = h.get<float>(76) < 0 ? -1.0 : 1.0;
  const double pix[3] = {h.get<float>(80), h.get<float>(84), h.get<float>(88)};
  const double bcd = b * b + c * c + d * d;
  const std::string quaternion =
      "(" + numberText(b) + ", " + numberText(c) + ", " + numberText(d) + ")";
  if (!std::isfinite(bcd))
    h.fail("the qform quaternion (b, c, d) = " + quaternion + " is not finite");
  // b, c, d are a unit quaternion's last three: their squares sum to at most 1 (float
  // rounding aside, which niftilib normalises away as here).
  if (bcd > 1.0 + 1e-5) {
    h.fail("the qform quaternion (b, c, d) = " + quaternion +
           " is invalid: b^2 + c^2 + d^2 = " + numberText(bcd) + " exceeds 1");
  }
  if (!(std::isfinite(offset.x) && std::isfinite(offset.y) && std::isfinite(offset.z))) {
    h.fail("the qform offset (" + numberText(offset.x) + ", " + numberText(offset.y) + ", " +
           numberText(offset.z) + ") is not finite");
  }
  double a = 1.0 - bcd;
  if (a < 1e-7) {
    const double norm = std::sqrt(bcd);
    b /= norm;
    c /= norm;
    d /= norm;
    a = 0.0;
  } else {
    a = std::sqrt(a);
  }
  const double R[3][3] = {
      {a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)},
      {2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b)},
      {2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b}};
  for (int r = 0; r < 3; ++r) {
    m[r][0] = R[r][0] * pix[0];
    m[r][1] = R[r][1] * pix[1];
    m[r][2] = R[r][2] * pix[2] * qfac;
  }
  centre0 = offset;
}

// The grid's affine in LPS: the sform if set, else the qform, else pixdim alone.
void affineOf(const NiftiHeader& h, double m[3][3], glm::dvec3& centre0) {
  const int sform = h.get<std::int16_t>(254);
  const int qform = h.get<std::int16_t>(252);
  if (sform > 0) {
    for (std::size_t r = 0; r < 3; ++r) {
      for (std::size_t c = 0; c < 3; ++c) m[r][c] = h.get<float>(280 + 16 * r + 4 * c);
      centre0[int(r)] = h.get<float>(280 + 16 * r + 12);
    }
    for (int r = 0; r < 3; ++r) {
      const char* name[3] = {"srow_x", "srow_y", "srow_z"};
      if (!std::isfinite(m[r][0]) || !std::isfinite(m[r][1]) || !std::isfinite(m[r][2]) ||
          !std::isfinite(centre0[r])) {
        h.fail(std::string("the sform is not finite (") + name[r] + " = " + numberText(m[r][0]) +
               " " + numberText(m[r][1]) + " " + numberText(m[r][2]) + " " +
               numberText(centre0[r]) + ")");
      }
    }
  } else if (qform > 0) {
    qformAffine(h, m, centre0);
  } else {
    const double pix[3] = {h.get<float>(80), h.get<float>(84), h.get<float>(88)};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m[r][c] = r == c ? pix[r] : 0.0;
    }
    centre0 = glm::dvec3(0.0);
  }
  // RAS -> LPS: negate x and y rows.
  for (int c = 0; c < 3; ++c) {
    m[0][c] = -m[0][c];
    m[1][c] = -m[1][c];
  }
  centre0.x = -centre0.x;
  centre0.y = -centre0.y;
}

glm::ivec3 sizesOf(const NiftiHeader& h) {
  const int ndim = h.get<std::int16_t>(40);
  // dim[0] counts the dimensions that follow, 1 to 7; anything else is not a NIfTI header.
  if (ndim < 1 || ndim > 7)
    h.fail("dim[0] = " + std::to_string(ndim) + " is not a number of dimensions (1 to 7)");
  std::vector<double> sizes;
  for (std::size_t a = 0; a < 3; ++a) sizes.push_back(h.get<std::int16_t>(42 + 2 * a));
  for (int a = 3; a < ndim && a < 7; ++a) {
    if (h.get<std::int16_t>(42 + 2 * std::size_t(a)) > 1)
      h.fail("dimension " + std::to_string(ndim) + " is not supported (need 3)");
  }
  if (ndim < 3) h.fail("dimension " + std::to_string(ndim) + " is not supported (need 3)");
  return checkVolumeSizes(h.path, sizes);
}

// The data after vox_offset, whole and checked (gzip: its trailer too).
std::vector<unsigned char> readData(const NiftiHeader& h, gzFile gz, glm::ivec3 sizes,
                                    const Scalar& s) {
  const float voxOffset = h.get<float>(108);
  if (!(voxOffset >= 348.0f) || voxOffset > 1e8f)
    h.fail("vox_offset " + numberText(voxOffset) + " is not at or after the header");
  // Skipped a chunk at a time: vox_offset may be up to 1e8 bytes past the header.
  std::vector<unsigned char> skip(65536);
  for (std::size_t left = std::size_t(voxOffset) - 348; left > 0;) {
    const unsigned chunk = unsigned(std::min(left, skip.size()));
    if (gzread(gz, skip.data(), chunk) != int(chunk)) h.fail("truncated before the data");
    left -= chunk;
  }
  const std::uint64_t count =
      std::uint64_t(sizes.x) * std::uint64_t(sizes.y) * std::uint64_t(sizes.z);
  const std::uint64_t expected = count * s.bytes;
  std::error_code ec;
  const std::uint64_t fileBytes = fs::file_size(h.path, ec);
  const bool gzipped = gzdirect(gz) == 0;
  if (!ec && expected > (gzipped ? fileBytes * nrrd::kMaxDeflateRatio + 1024 : fileBytes)) {
    h.fail("truncated: the file (" + std::to_string(fileBytes) + " bytes" +
           (gzipped ? ", gzip" : "") + ") cannot hold the " + std::to_string(expected) +
           " bytes of data the sizes need");
  }
  refuseOverVolumeMemory(h.path, sizes, s.bytes);
  std::vector<unsigned char> raw(expected);
  std::uint64_t got = 0;
  while (got < expected) {
    const unsigned chunk = unsigned(std::min<std::uint64_t>(expected - got, 1u << 30));
    const int n = gzread(gz, raw.data() + got, chunk);
    if (n <= 0) break;
    got += std::uint64_t(n);
  }
  if (got < expected)
    h.fail("truncated: " + std::to_string(got) + " bytes of data, sizes need " +
           std::to_string(expected));
  if (gzipped) {
    // zlib checks the stream's trailer (CRC and length) only when asked past the data.
    unsigned char extra = 0;
    int err = Z_OK;
    if (gzread(gz, &extra, 1) < 0 || (gzerror(gz, &err), err != Z_OK))
      h.fail("truncated: the gzip stream ends before its checksum");
  }
  return raw;
}

}  // namespace

RawVolume readNiftiVolume(const std::string& path) {
  NiftiHeader h;
  h.path = path;
  requireInputFile(path);
  gzFile gz = gzopen(path.c_str(), "rb");  // plain files are read as they are
  if (!gz) h.fail("cannot open (" + std::string(std::strerror(errno)) + ")");
  struct Closer {
    gzFile f;
    ~Closer() { gzclose(f); }
  } closer{gz};
  if (gzread(gz, h.bytes, 348) != 348)
    h.fail("not a NIfTI-1 file (shorter than its 348-byte header)");
  h.swap = at<std::int32_t>(h.bytes, 0, false) != 348;
  if (h.get<std::int32_t>(0) != 348) h.fail("not a NIfTI-1 file (sizeof_hdr is not 348)");
  if (std::memcmp(h.bytes + 344, "n+1", 4) != 0) {
    if (std::memcmp(h.bytes + 344, "ni1", 4) == 0)
      h.fail("a NIfTI .hdr/.img pair: save as a single .nii file");
    h.fail("not a NIfTI-1 file (no 'n+1' magic)");
  }
  RawVolume v;
  v.sizes = sizesOf(h);
  const Scalar s = scalarOf(h);
  const float slope = h.get<float>(112);
  const float inter = h.get<float>(116);
  const bool scaled = std::isfinite(slope) && slope != 0.0f && (slope != 1.0f || inter != 0.0f);
  if (scaled && !std::isfinite(inter)) {
    h.fail("scl_inter " + numberText(inter) + " is not finite (scl_slope " + numberText(slope) +
           ")");
  }
  v.type = s.name;
  v.integer = s.integer && !scaled;
  v.isSigned = s.isSigned || (scaled && (slope < 0 || inter < 0));
  double m[3][3];
  glm::dvec3 centre0;
  affineOf(h, m, centre0);
  std::vector<unsigned char> raw = readData(h, gz, v.sizes, s);
  const std::size_t count =
      std::size_t(v.sizes.x) * std::size_t(v.sizes.y) * std::size_t(v.sizes.z);
  setVolumeValues(s, h.swap, std::move(raw), count, v);
  if (scaled) {
    v.slope = slope;
    v.intercept = inter;
  }
  placeVolume(path, m, centre0, v);
  return v;
}

}  // namespace osteon::geometry
