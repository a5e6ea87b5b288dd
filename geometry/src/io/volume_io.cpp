#include "osteon/geometry/io/volume_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <zlib.h>

#include "io/nrrd_header.h"
#include "io/volume_readers.h"
#include "osteon/core/constants.h"
#include "osteon/core/error.h"
#include "osteon/core/input_file.h"
#include "osteon/core/memory.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/nrrd_io.h"

namespace osteon::geometry {

namespace fs = std::filesystem;

namespace {

using nrrd::excerpt;
using nrrd::parseNumbers;
using nrrd::trim;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

using nrrd::Scalar;  // a scalar type: its name, width and how to read one value

// Makes `bytes` (count values of `s` in the file's byte order) the volume's values, in the
// host's order (little-endian hosts only, as osteon's targets), in place: no second copy.
void decode(const Scalar& s, bool bigEndian, std::vector<unsigned char>&& bytes, std::size_t count,
            RawVolume& v) {
  bytes.resize(count * s.bytes);
  if (bigEndian && s.bytes > 1) {
    for (std::size_t i = 0; i < count; ++i)
      std::reverse(bytes.begin() + std::ptrdiff_t(i * s.bytes),
                   bytes.begin() + std::ptrdiff_t((i + 1) * s.bytes));
  }
  v.data = std::move(bytes);
  v.type = s.name;
  v.scalarBytes = s.bytes;
}

// A volume past the machine's memory is refused before any of it is allocated, naming the file
// and what would help (a volume has no --voxel-size to raise).
void refuseOverVolumeMemory(const std::string& path, glm::ivec3 sizes, std::size_t scalarBytes) {
  refuseOverMemory(
      path + ": a " + std::to_string(sizes.x) + " x " + std::to_string(sizes.y) + " x " +
          std::to_string(sizes.z) + " volume",
      volumeLoadMemoryBytes(sizes, scalarBytes),
      "crop or downsample it (fewer voxels) before loading, or use a machine with more memory");
}

// NaN or infinite voxels are refused wherever they are, before anything reads them as numbers
// (a NaN compares false with every threshold and would read as air); positions are the file's
// voxel indices (i fastest), as other tools show them.
template <typename T>
void refuseNonFinite(const std::string& path, const RawVolume& v, StoredValues<T> values) {
  if constexpr (std::is_floating_point_v<T>) {
    const std::size_t count = std::size_t(v.sizes.x) * v.sizes.y * v.sizes.z;
    std::size_t bad = 0, first = 0;
    for (std::size_t i = 0; i < count; ++i) {
      if (!std::isfinite(values[i])) {
        if (bad++ == 0) first = i;
      }
    }
    if (bad == 0) return;
    const std::size_t nx = std::size_t(v.sizes.x), nxy = nx * std::size_t(v.sizes.y);
    const T firstValue = values[first];
    throw InputError(path + ": " + std::to_string(bad) + " of " + std::to_string(count) +
                     " voxels " + (bad == 1 ? "is" : "are") + " not a finite number (" + v.type +
                     " NaN or infinite), the first (" +
                     (std::isnan(firstValue) ? "NaN"
                      : firstValue > 0       ? "+Inf"
                                             : "-Inf") +
                     ") at voxel (" + std::to_string(first % nx) + ", " +
                     std::to_string(first / nx % std::size_t(v.sizes.y)) + ", " +
                     std::to_string(first / nxy) + ")");
  }
}

// Axis-aligned geometry from a 3x3 direction matrix (columns = axes i, j, k in LPS) and the
// centre of voxel (0,0,0): reorders axes stored in another order than L, P, S (a permuted
// matrix), flips axes that run backwards, refuses rotation and anisotropy. Every volume comes
// through here, so its values are checked here too.
void placeVolume(const std::string& path, const double m[3][3], glm::dvec3 centre0, RawVolume& v) {
  v.visit([&](auto values) { refuseNonFinite(path, v, values); });
  if (!(std::isfinite(centre0.x) && std::isfinite(centre0.y) && std::isfinite(centre0.z))) {
    throw InputError(path + ": the origin (" + numberText(centre0.x) + ", " +
                     numberText(centre0.y) + ", " + numberText(centre0.z) + ") is not finite");
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!(std::isfinite(m[0][axis]) && std::isfinite(m[1][axis]) && std::isfinite(m[2][axis]))) {
      throw InputError(path + ": the direction of axis " + std::to_string(axis) + " (" +
                       numberText(m[0][axis]) + ", " + numberText(m[1][axis]) + ", " +
                       numberText(m[2][axis]) + ") is not finite");
    }
  }
  double spacing[3];
  int flip[3];
  int row[3];  // the LPS axis each stored axis runs along
  for (int axis = 0; axis < 3; ++axis) {
    const double scale =
        std::max({std::abs(m[0][axis]), std::abs(m[1][axis]), std::abs(m[2][axis])});
    if (!(scale > 0.0) || !std::isfinite(scale)) {
      throw InputError(path + ": the voxel spacing of axis " + std::to_string(axis) + " is " +
                       (std::isfinite(scale) ? "zero" : "not a finite number"));
    }
    // Below a nanometre no scanner samples; such a spacing is a corrupt header.
    if (scale < 1e-6) {
      throw InputError(path + ": the voxel spacing of axis " + std::to_string(axis) + " is " +
                       numberText(scale) + " mm, below 1 nm");
    }
    row[axis] = std::abs(m[0][axis]) == scale ? 0 : std::abs(m[1][axis]) == scale ? 1 : 2;
    for (int r = 0; r < 3; ++r) {
      if (r != row[axis] && std::abs(m[r][axis]) > 1e-6 * scale) {
        throw InputError(path + ": space directions are not axis-aligned (axis " +
                         std::to_string(axis) + " points along (" + numberText(m[0][axis]) + ", " +
                         numberText(m[1][axis]) + ", " + numberText(m[2][axis]) +
                         ")); rotated volumes are not supported: resample to an "
                         "axis-aligned grid");
      }
    }
    for (int other = 0; other < axis; ++other) {
      if (row[other] == row[axis]) {
        throw InputError(path + ": space directions of axes " + std::to_string(other) + " and " +
                         std::to_string(axis) + " both run along " + "LPS"[row[axis]] +
                         " (a degenerate direction matrix)");
      }
    }
    spacing[axis] = scale;
    flip[axis] = m[row[axis]][axis] < 0.0;
  }
  if (std::abs(spacing[0] - spacing[1]) > 1e-6 * spacing[0] ||
      std::abs(spacing[0] - spacing[2]) > 1e-6 * spacing[0]) {
    throw InputError(path + ": anisotropic spacing " + numberText(spacing[0]) + " x " +
                     numberText(spacing[1]) + " x " + numberText(spacing[2]) +
                     " mm is not supported (voxels must be cubes: resample first)");
  }
  v.voxelSizeMm = (spacing[0] + spacing[1] + spacing[2]) / 3.0;
  const glm::ivec3 stored = v.sizes;
  glm::ivec3 placed;
  glm::dvec3 lowCentre;
  for (int a = 0; a < 3; ++a) {
    placed[row[a]] = stored[a];
    lowCentre[row[a]] =
        flip[a] ? centre0[row[a]] - double(stored[a] - 1) * v.voxelSizeMm : centre0[row[a]];
  }
  v.sizes = placed;
  v.originMm = lowCentre - 0.5 * v.voxelSizeMm;
  for (int a = 0; a < 3; ++a) {
    if (!(std::abs(v.originMm[a]) <= kMaxCoordinateMm) ||
        !(std::abs(v.originMm[a] + v.sizes[a] * v.voxelSizeMm) <= kMaxCoordinateMm)) {
      throw InputError(path + ": voxel size " + numberText(v.voxelSizeMm) +
                       " mm puts the volume at " +
                       numberText(v.originMm[a] + v.sizes[a] * v.voxelSizeMm) + " mm on axis " +
                       std::to_string(a) + ", beyond +-1e9 mm (1000 km)");
    }
  }
  if (flip[0] || flip[1] || flip[2] || row[0] != 0 || row[1] != 1 || row[2] != 2) {
    // Stored voxel (i, j, k) goes to placed index p[row[a]] = i_a (or its mirror).
    const std::size_t bytes = v.scalarBytes;
    std::vector<unsigned char> out(v.data.size());
    std::size_t step[3];  // placed offset of one step along each stored axis
    std::size_t start = 0;
    const std::size_t placedStride[3] = {1, std::size_t(placed.x),
                                         std::size_t(placed.x) * std::size_t(placed.y)};
    for (int a = 0; a < 3; ++a) {
      step[a] = placedStride[row[a]];
      if (flip[a]) start += std::size_t(stored[a] - 1) * step[a];
    }
    const auto signedStep = [&](int a) {
      return flip[a] ? -std::ptrdiff_t(step[a]) : std::ptrdiff_t(step[a]);
    };
    std::size_t from = 0;
    for (int k = 0; k < stored.z; ++k) {
      for (int j = 0; j < stored.y; ++j) {
        std::ptrdiff_t to = std::ptrdiff_t(start) + k * signedStep(2) + j * signedStep(1);
        for (int i = 0; i < stored.x; ++i, ++from, to += signedStep(0)) {
          std::memcpy(&out[std::size_t(to) * bytes], &v.data[from * bytes], bytes);
        }
      }
    }
    v.data.swap(out);
  }
}

glm::ivec3 checkSizes(const std::string& path, const std::vector<double>& s) {
  std::uint64_t voxels = 1;
  glm::ivec3 n;
  for (int a = 0; a < 3; ++a) {
    if (!(s[a] >= 1 && s[a] <= double(1 << 30) && s[a] == std::floor(s[a]))) {
      throw InputError(path + ": sizes are not three integers from 1 to 2^30");
    }
    n[a] = int(s[a]);
    voxels *= std::uint64_t(n[a]);
    if (voxels > VoxelGrid::kMaxVoxels) throw InputError(path + ": sizes exceed 2^32 voxels");
  }
  return n;
}

RawVolume readNrrdVolume(const std::string& path, bool allowOutsideData) {
  const nrrd::Header h = nrrd::readHeader(path);
  const auto fail = [&h](const std::string& reason) { h.fail(reason); };
  const auto field = [&h](const char* name) { return h.field(name); };
  RawVolume v;
  // osteon's own grid only by all it writes: a user's file with one osteon_* key is a volume.
  switch (nrrd::osteonFile(h)) {
    case nrrd::OsteonFile::Fill:
      v.osteonGrid = true;
      return v;
    case nrrd::OsteonFile::Density:
      h.fail(
          "an osteon density file (it goes with a grid's fill file): open the grid's .nrrd beside "
          "it, "
          "without '.density'");
    case nrrd::OsteonFile::None:
      break;
  }
  v.sizes = nrrd::readSizes(h);
  const nrrd::Layout layout = nrrd::readLayout(h);
  const nrrd::Scalar& scalar = layout.scalar;
  v.type = scalar.name;
  v.integer = scalar.integer;
  v.isSigned = scalar.isSigned;
  const bool gzip = layout.gzip;
  const bool bigEndian = layout.bigEndian;
  const std::string* space = field("space");
  const std::string* spacings = field("spacings");
  if (space || spacings) {
    const std::string s = space ? lower(trim(*space)) : "lps";
    if (s != "left-posterior-superior" && s != "lps" && s != "right-anterior-superior" &&
        s != "ras") {
      fail("space " + excerpt(s) + " is not supported (LPS or RAS)");
    }
    const bool ras = s == "right-anterior-superior" || s == "ras";
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    glm::dvec3 centre0(0.0);
    if (!space) {
      std::vector<double> sp;
      if (!parseNumbers(*spacings, sp) || sp.size() != 3 || !(sp[0] > 0) || !(sp[1] > 0) ||
          !(sp[2] > 0)) {
        fail("spacings " + excerpt(*spacings) + " are not three positive numbers");
      }
      for (int a = 0; a < 3; ++a) m[a][a] = sp[a];
    } else if (const std::string* dirs = field("spacedirections")) {
      std::vector<double> d;
      if (!parseNumbers(*dirs, d) || d.size() != 9)
        fail("space directions " + excerpt(*dirs) + " are not three 3-vectors");
      for (int axis = 0; axis < 3; ++axis) {
        for (int r = 0; r < 3; ++r) m[r][axis] = d[axis * 3 + r];
      }
    } else {
      fail("'space' without 'space directions'");
    }
    if (const std::string* origin = field("spaceorigin")) {
      std::vector<double> o;
      if (!parseNumbers(*origin, o) || o.size() != 3)
        fail("space origin " + excerpt(*origin) + " is not a 3-vector");
      centre0 = glm::dvec3(o[0], o[1], o[2]);
    }
    if (ras) {
      for (int axis = 0; axis < 3; ++axis) {
        m[0][axis] = -m[0][axis];
        m[1][axis] = -m[1][axis];
      }
      centre0.x = -centre0.x;
      centre0.y = -centre0.y;
    }
    const std::uint64_t count = std::uint64_t(v.sizes.x) * v.sizes.y * v.sizes.z;
    const std::uint64_t expected = count * scalar.bytes;
    // Where the data lies and how long it is, known before a byte of it is read.
    const nrrd::DataLocation at = nrrd::locateData(h, expected, gzip, allowOutsideData);
    refuseOverVolumeMemory(path, v.sizes, scalar.bytes);
    std::vector<unsigned char> raw;
    if (gzip) {
      raw = nrrd::inflateData(at, expected);
    } else {
      raw.resize(expected);
      std::ifstream data = nrrd::openData(at);
      if (!data.read(reinterpret_cast<char*>(raw.data()), std::streamsize(raw.size()))) {
        throw InputError(at.shown + ": read failed in the data");
      }
    }
    decode(scalar, bigEndian, std::move(raw), count, v);
    placeVolume(path, m, centre0, v);
    return v;
  }
  fail("no spacing ('space' with 'space directions', or 'spacings' field)");
  return v;
}

// ---- NIfTI-1 ----

template <typename T>
T at(const unsigned char* h, std::size_t offset, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, h + offset, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

RawVolume readNiftiVolume(const std::string& path) {
  const auto fail = [&path](const std::string& reason) { throw InputError(path + ": " + reason); };
  requireInputFile(path);
  gzFile gz = gzopen(path.c_str(), "rb");  // plain files are read as they are
  if (!gz) fail("cannot open (" + std::string(std::strerror(errno)) + ")");
  struct Closer {
    gzFile f;
    ~Closer() { gzclose(f); }
  } closer{gz};
  unsigned char h[352];
  if (gzread(gz, h, 348) != 348) fail("not a NIfTI-1 file (shorter than its 348-byte header)");
  const bool swap = at<std::int32_t>(h, 0, false) != 348;
  if (at<std::int32_t>(h, 0, swap) != 348) fail("not a NIfTI-1 file (sizeof_hdr is not 348)");
  if (std::memcmp(h + 344, "n+1", 4) != 0) {
    if (std::memcmp(h + 344, "ni1", 4) == 0)
      fail("a NIfTI .hdr/.img pair: save as a single .nii file");
    fail("not a NIfTI-1 file (no 'n+1' magic)");
  }
  const int ndim = at<std::int16_t>(h, 40, swap);
  // dim[0] counts the dimensions that follow, 1 to 7; anything else is not a NIfTI header.
  if (ndim < 1 || ndim > 7)
    fail("dim[0] = " + std::to_string(ndim) + " is not a number of dimensions (1 to 7)");
  std::vector<double> sizes;
  for (int a = 0; a < 3; ++a) sizes.push_back(at<std::int16_t>(h, 42 + 2 * a, swap));
  for (int a = 3; a < ndim && a < 7; ++a) {
    if (at<std::int16_t>(h, 42 + 2 * a, swap) > 1)
      fail("dimension " + std::to_string(ndim) + " is not supported (need 3)");
  }
  if (ndim < 3) fail("dimension " + std::to_string(ndim) + " is not supported (need 3)");
  RawVolume v;
  v.sizes = checkSizes(path, sizes);
  const int datatype = at<std::int16_t>(h, 70, swap);
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
      fail("datatype " + std::to_string(datatype) + " is not a supported scalar type");
  }
  // bitpix must say the datatype's width: a header that disagrees with itself is not trusted.
  const int bitpix = at<std::int16_t>(h, 72, swap);
  if (bitpix != int(8 * s.bytes)) {
    fail("bitpix " + std::to_string(bitpix) + " does not match datatype " +
         std::to_string(datatype) + " (" + s.name + ", " + std::to_string(8 * s.bytes) + " bits)");
  }
  const float voxOffset = at<float>(h, 108, swap);
  const float slope = at<float>(h, 112, swap);
  const float inter = at<float>(h, 116, swap);
  const bool scaled = std::isfinite(slope) && slope != 0.0f && (slope != 1.0f || inter != 0.0f);
  if (scaled && !std::isfinite(inter))
    fail("scl_inter " + numberText(inter) + " is not finite (scl_slope " + numberText(slope) + ")");
  v.type = s.name;
  v.integer = s.integer && !scaled;
  v.isSigned = s.isSigned || (scaled && (slope < 0 || inter < 0));
  // RAS -> LPS: negate x and y rows.
  double m[3][3];
  glm::dvec3 centre0;
  const int sform = at<std::int16_t>(h, 254, swap);
  const int qform = at<std::int16_t>(h, 252, swap);
  const double qfac = at<float>(h, 76, swap) < 0 ? -1.0 : 1.0;
  const double pix[3] = {at<float>(h, 80, swap), at<float>(h, 84, swap), at<float>(h, 88, swap)};
  if (sform > 0) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m[r][c] = at<float>(h, 280 + 16 * r + 4 * c, swap);
      centre0[r] = at<float>(h, 280 + 16 * r + 12, swap);
    }
    for (int r = 0; r < 3; ++r) {
      const char* name[3] = {"srow_x", "srow_y", "srow_z"};
      if (!std::isfinite(m[r][0]) || !std::isfinite(m[r][1]) || !std::isfinite(m[r][2]) ||
          !std::isfinite(centre0[r])) {
        fail(std::string("the sform is not finite (") + name[r] + " = " + numberText(m[r][0]) +
             " " + numberText(m[r][1]) + " " + numberText(m[r][2]) + " " + numberText(centre0[r]) +
             ")");
      }
    }
  } else if (qform > 0) {
    double b = at<float>(h, 256, swap), c = at<float>(h, 260, swap), d = at<float>(h, 264, swap);
    const glm::dvec3 offset(at<float>(h, 268, swap), at<float>(h, 272, swap),
                            at<float>(h, 276, swap));
    const double bcd = b * b + c * c + d * d;
    const std::string quaternion =
        "(" + numberText(b) + ", " + numberText(c) + ", " + numberText(d) + ")";
    if (!std::isfinite(bcd))
      fail("the qform quaternion (b, c, d) = " + quaternion + " is not finite");
    // b, c, d are a unit quaternion's last three: their squares sum to at most 1 (float
    // rounding aside, which niftilib normalises away as here).
    if (bcd > 1.0 + 1e-5) {
      fail("the qform quaternion (b, c, d) = " + quaternion +
           " is invalid: b^2 + c^2 + d^2 = " + numberText(bcd) + " exceeds 1");
    }
    if (!(std::isfinite(offset.x) && std::isfinite(offset.y) && std::isfinite(offset.z))) {
      fail("the qform offset (" + numberText(offset.x) + ", " + numberText(offset.y) + ", " +
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
  } else {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m[r][c] = r == c ? pix[r] : 0.0;
    }
    centre0 = glm::dvec3(0.0);
  }
  for (int c = 0; c < 3; ++c) {
    m[0][c] = -m[0][c];
    m[1][c] = -m[1][c];
  }
  centre0.x = -centre0.x;
  centre0.y = -centre0.y;

  if (!(voxOffset >= 348.0f) || voxOffset > 1e8f)
    fail("vox_offset " + numberText(voxOffset) + " is not at or after the header");
  // Skipped a chunk at a time: vox_offset may be up to 1e8 bytes past the header.
  std::vector<unsigned char> skip(65536);
  for (std::size_t left = std::size_t(voxOffset) - 348; left > 0;) {
    const unsigned chunk = unsigned(std::min(left, skip.size()));
    if (gzread(gz, skip.data(), chunk) != int(chunk)) fail("truncated before the data");
    left -= chunk;
  }
  const std::uint64_t count = std::uint64_t(v.sizes.x) * v.sizes.y * v.sizes.z;
  const std::uint64_t expected = count * s.bytes;
  std::error_code ec;
  const std::uint64_t fileBytes = fs::file_size(path, ec);
  const bool gzipped = gzdirect(gz) == 0;
  if (!ec && expected > (gzipped ? fileBytes * nrrd::kMaxDeflateRatio + 1024 : fileBytes)) {
    fail("truncated: the file (" + std::to_string(fileBytes) + " bytes" +
         (gzipped ? ", gzip" : "") + ") cannot hold the " + std::to_string(expected) +
         " bytes of data the sizes need");
  }
  refuseOverVolumeMemory(path, v.sizes, s.bytes);
  std::vector<unsigned char> raw(expected);
  std::uint64_t got = 0;
  while (got < expected) {
    const unsigned chunk = unsigned(std::min<std::uint64_t>(expected - got, 1u << 30));
    const int n = gzread(gz, raw.data() + got, chunk);
    if (n <= 0) break;
    got += std::uint64_t(n);
  }
  if (got < expected)
    fail("truncated: " + std::to_string(got) + " bytes of data, sizes need " +
         std::to_string(expected));
  if (gzipped) {
    // zlib checks the stream's trailer (CRC and length) only when asked past the data.
    unsigned char extra = 0;
    int err = Z_OK;
    if (gzread(gz, &extra, 1) < 0 || (gzerror(gz, &err), err != Z_OK))
      fail("truncated: the gzip stream ends before its checksum");
  }
  decode(s, swap, std::move(raw), count, v);
  if (scaled) {
    v.slope = slope;
    v.intercept = inter;
  }
  placeVolume(path, m, centre0, v);
  return v;
}

}  // namespace

bool isVolumePath(const std::string& path) {
  const std::string p = lower(path);
  return endsWith(p, ".nrrd") || endsWith(p, ".nhdr") || endsWith(p, ".nii") ||
         endsWith(p, ".nii.gz") || io::isMetaImagePath(path) || io::isDicomPath(path);
}

std::string volumeFormat(const std::string& path) {
  const std::string p = lower(path);
  if (endsWith(p, ".nii") || endsWith(p, ".nii.gz")) return "nifti";
  if (io::isMetaImagePath(path)) return "metaimage";
  if (io::isDicomPath(path)) return "dicom";
  return "nrrd";
}

RawVolume readRawVolume(const std::string& path, bool allowOutsideData) {
  const std::string p = lower(path);
  if (endsWith(p, ".nii") || endsWith(p, ".nii.gz")) return readNiftiVolume(path);
  return readNrrdVolume(path, allowOutsideData);
}

RawVolume readRawVolume(const std::string& path, const VolumeOptions& options) {
  const std::string format = volumeFormat(path);
  if (!options.series.empty() && format != "dicom") {
    throw InputError("--series " + options.series + ": only for DICOM; " + path + " is " + format);
  }
  if (format != "metaimage" && format != "dicom")
    return readRawVolume(path, options.allowOutsideData);
  io::StoredVolume s = format == "dicom" ? io::readDicom(path, options.series)
                                         : io::readMetaImage(path, options.allowOutsideData);
  placeVolume(path, s.m, s.centre0, s.volume);
  return std::move(s.volume);
}

}  // namespace osteon::geometry
