#include "osteon/geometry/io/volume_io.h"

#include <zlib.h>

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

#include "osteon/core/constants.h"
#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/io/mesh_io.h"
#include "io/nrrd_header.h"

namespace osteon::geometry {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

std::string shortNum(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string excerpt(const std::string& s) {
  std::string out = "'";
  for (unsigned char c : s.substr(0, 60)) out += std::isprint(c) ? char(c) : '?';
  return out + (s.size() > 60 ? "...'" : "'");
}

bool parseNumbers(std::string text, std::vector<double>& values) {
  for (char& c : text) {
    if (c == '(' || c == ')' || c == ',') c = ' ';
  }
  values.clear();
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  std::string token;
  while (in >> token) {
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end != token.c_str() + token.size() || !std::isfinite(v)) return false;
    values.push_back(v);
  }
  return true;
}

using nrrd::Scalar;  // a scalar type: its name, width and how to read one value

// Decodes `count` values of `s` from `bytes` into doubles.
void decode(const Scalar& s, bool bigEndian, const unsigned char* bytes, std::size_t count,
            std::vector<double>& out) {
  out.resize(count);
  unsigned char v[8];
  for (std::size_t i = 0; i < count; ++i) {
    const unsigned char* p = bytes + i * s.bytes;
    for (std::size_t b = 0; b < s.bytes; ++b) {
      // to the host's order (little-endian hosts only, as osteon's targets)
      v[b] = bigEndian ? p[s.bytes - 1 - b] : p[b];
    }
    double d = 0.0;
    if (!s.integer) {
      if (s.bytes == 4) {
        float f;
        std::memcpy(&f, v, 4);
        d = f;
      } else {
        std::memcpy(&d, v, 8);
      }
    } else {
      std::uint64_t u = 0;
      for (std::size_t b = 0; b < s.bytes; ++b) u |= std::uint64_t(v[b]) << (8 * b);
      if (s.isSigned && s.bytes < 8 && (u >> (8 * s.bytes - 1)) & 1u) {
        u |= ~std::uint64_t(0) << (8 * s.bytes);
      }
      d = s.isSigned ? double(std::int64_t(u)) : double(u);
    }
    out[i] = d;
  }
}

// A volume is read as its stored values, then decoded to doubles, then made a grid (fill and
// density per voxel): a size past the machine's memory is refused before any of it is allocated.
void refuseOverVolumeMemory(const std::string& path, glm::ivec3 sizes, int scalarBytes) {
  const double voxels = double(sizes.x) * sizes.y * sizes.z;
  refuseOverMemory(path + ": a " + std::to_string(sizes.x) + " x " + std::to_string(sizes.y) + " x " +
                       std::to_string(sizes.z) + " volume",
                   voxels * double(scalarBytes + sizeof(double) + sizeof(std::uint16_t) + sizeof(std::int16_t)), "");
}

// Axis-aligned geometry from a 3x3 direction matrix (columns = axes i, j, k in LPS) and the
// centre of voxel (0,0,0): flips axes that run backwards, refuses rotation and anisotropy.
void placeVolume(const std::string& path, const double m[3][3], glm::dvec3 centre0, RawVolume& v) {
  double spacing[3];
  int flip[3];
  for (int axis = 0; axis < 3; ++axis) {
    const double scale = std::max({std::abs(m[0][axis]), std::abs(m[1][axis]), std::abs(m[2][axis])});
    if (!(scale > 0.0) || !std::isfinite(scale)) {
      throw InputError(path + ": the voxel spacing of axis " + std::to_string(axis) + " is " +
                       (std::isfinite(scale) ? "zero" : "not a finite number"));
    }
    // Below a nanometre no scanner samples; such a spacing is a corrupt header.
    if (scale < 1e-6) {
      throw InputError(path + ": the voxel spacing of axis " + std::to_string(axis) + " is " + shortNum(scale) +
                       " mm, below 1 nm");
    }
    for (int r = 0; r < 3; ++r) {
      if (r != axis && std::abs(m[r][axis]) > 1e-6 * scale) {
        throw InputError(path + ": space directions are not axis-aligned (axis " + std::to_string(axis) +
                         " points along (" + shortNum(m[0][axis]) + ", " + shortNum(m[1][axis]) + ", " +
                         shortNum(m[2][axis]) + ")); rotated volumes are not supported: resample to an "
                         "axis-aligned grid");
      }
    }
    spacing[axis] = std::abs(m[axis][axis]);
    flip[axis] = m[axis][axis] < 0.0;
  }
  if (std::abs(spacing[0] - spacing[1]) > 1e-6 * spacing[0] || std::abs(spacing[0] - spacing[2]) > 1e-6 * spacing[0]) {
    throw InputError(path + ": anisotropic spacing " + shortNum(spacing[0]) + " x " + shortNum(spacing[1]) + " x " +
                     shortNum(spacing[2]) + " mm is not supported (voxels must be cubes: resample first)");
  }
  v.voxelSizeMm = (spacing[0] + spacing[1] + spacing[2]) / 3.0;
  glm::dvec3 lowCentre = centre0;
  for (int a = 0; a < 3; ++a) {
    if (flip[a]) lowCentre[a] = centre0[a] - double(v.sizes[a] - 1) * v.voxelSizeMm;
  }
  v.originMm = lowCentre - 0.5 * v.voxelSizeMm;
  for (int a = 0; a < 3; ++a) {
    if (!(std::abs(v.originMm[a]) <= kMaxCoordinateMm) ||
        !(std::abs(v.originMm[a] + v.sizes[a] * v.voxelSizeMm) <= kMaxCoordinateMm)) {
      throw InputError(path + ": voxel size " + shortNum(v.voxelSizeMm) + " mm puts the volume at " +
                       shortNum(v.originMm[a] + v.sizes[a] * v.voxelSizeMm) + " mm on axis " + std::to_string(a) +
                       ", beyond +-1e9 mm (1000 km)");
    }
  }
  if (flip[0] || flip[1] || flip[2]) {
    const glm::ivec3 n = v.sizes;
    std::vector<double> out(v.values.size());
    for (int z = 0; z < n.z; ++z) {
      for (int y = 0; y < n.y; ++y) {
        for (int x = 0; x < n.x; ++x) {
          const int sx = flip[0] ? n.x - 1 - x : x, sy = flip[1] ? n.y - 1 - y : y, sz = flip[2] ? n.z - 1 - z : z;
          out[(std::size_t(z) * n.y + y) * n.x + x] = v.values[(std::size_t(sz) * n.y + sy) * n.x + sx];
        }
      }
    }
    v.values.swap(out);
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
      h.fail("an osteon density file (it goes with a grid's fill file): open the grid's .nrrd beside it, "
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
    if (s != "left-posterior-superior" && s != "lps" && s != "right-anterior-superior" && s != "ras") {
      fail("space " + excerpt(s) + " is not supported (LPS or RAS)");
    }
    const bool ras = s == "right-anterior-superior" || s == "ras";
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    glm::dvec3 centre0(0.0);
    if (!space) {
      std::vector<double> sp;
      if (!parseNumbers(*spacings, sp) || sp.size() != 3 || !(sp[0] > 0) || !(sp[1] > 0) || !(sp[2] > 0)) {
        fail("spacings " + excerpt(*spacings) + " are not three positive numbers");
      }
      for (int a = 0; a < 3; ++a) m[a][a] = sp[a];
    } else if (const std::string* dirs = field("spacedirections")) {
      std::vector<double> d;
      if (!parseNumbers(*dirs, d) || d.size() != 9) fail("space directions " + excerpt(*dirs) + " are not three 3-vectors");
      for (int axis = 0; axis < 3; ++axis) {
        for (int r = 0; r < 3; ++r) m[r][axis] = d[axis * 3 + r];
      }
    } else {
      fail("'space' without 'space directions'");
    }
    if (const std::string* origin = field("spaceorigin")) {
      std::vector<double> o;
      if (!parseNumbers(*origin, o) || o.size() != 3) fail("space origin " + excerpt(*origin) + " is not a 3-vector");
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
    refuseOverVolumeMemory(path, v.sizes, int(scalar.bytes));
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
    decode(scalar, bigEndian, raw.data(), count, v.values);
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
  std::error_code ec;
  if (!fs::exists(path, ec)) fail("no such file");
  if (!fs::is_regular_file(path, ec)) fail("not a regular file");
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
    if (std::memcmp(h + 344, "ni1", 4) == 0) fail("a NIfTI .hdr/.img pair: save as a single .nii file");
    fail("not a NIfTI-1 file (no 'n+1' magic)");
  }
  const int ndim = at<std::int16_t>(h, 40, swap);
  std::vector<double> sizes;
  for (int a = 0; a < 3; ++a) sizes.push_back(at<std::int16_t>(h, 42 + 2 * a, swap));
  for (int a = 3; a < ndim && a < 7; ++a) {
    if (at<std::int16_t>(h, 42 + 2 * a, swap) > 1) fail("dimension " + std::to_string(ndim) + " is not supported (need 3)");
  }
  if (ndim < 3) fail("dimension " + std::to_string(ndim) + " is not supported (need 3)");
  RawVolume v;
  v.sizes = checkSizes(path, sizes);
  const int datatype = at<std::int16_t>(h, 70, swap);
  Scalar s;
  switch (datatype) {
    case 2: s = {"uint8", 1, true, false}; break;
    case 4: s = {"int16", 2, true, true}; break;
    case 8: s = {"int32", 4, true, true}; break;
    case 16: s = {"float", 4, false, true}; break;
    case 64: s = {"double", 8, false, true}; break;
    case 256: s = {"int8", 1, true, true}; break;
    case 512: s = {"uint16", 2, true, false}; break;
    case 768: s = {"uint32", 4, true, false}; break;
    case 1024: s = {"int64", 8, true, true}; break;
    case 1280: s = {"uint64", 8, true, false}; break;
    default: fail("datatype " + std::to_string(datatype) + " is not a supported scalar type");
  }
  const float voxOffset = at<float>(h, 108, swap);
  const float slope = at<float>(h, 112, swap);
  const float inter = at<float>(h, 116, swap);
  const bool scaled = std::isfinite(slope) && slope != 0.0f && (slope != 1.0f || inter != 0.0f);
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
  } else if (qform > 0) {
    double b = at<float>(h, 256, swap), c = at<float>(h, 260, swap), d = at<float>(h, 264, swap);
    double a = 1.0 - (b * b + c * c + d * d);
    a = a < 1e-7 ? 0.0 : std::sqrt(a);
    const double R[3][3] = {{a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)},
                            {2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b)},
                            {2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b}};
    for (int r = 0; r < 3; ++r) {
      m[r][0] = R[r][0] * pix[0];
      m[r][1] = R[r][1] * pix[1];
      m[r][2] = R[r][2] * pix[2] * qfac;
    }
    centre0 = {at<float>(h, 268, swap), at<float>(h, 272, swap), at<float>(h, 276, swap)};
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

  if (!(voxOffset >= 348.0f) || voxOffset > 1e8f) fail("vox_offset " + shortNum(voxOffset) + " is not at or after the header");
  std::vector<unsigned char> skip(std::size_t(voxOffset) - 348);
  if (!skip.empty() && gzread(gz, skip.data(), unsigned(skip.size())) != int(skip.size())) fail("truncated before the data");
  const std::uint64_t count = std::uint64_t(v.sizes.x) * v.sizes.y * v.sizes.z;
  const std::uint64_t expected = count * s.bytes;
  const std::uint64_t fileBytes = fs::file_size(path, ec);
  const bool gzipped = gzdirect(gz) == 0;
  if (!ec && expected > (gzipped ? fileBytes * nrrd::kMaxDeflateRatio + 1024 : fileBytes)) {
    fail("truncated: the file (" + std::to_string(fileBytes) + " bytes" + (gzipped ? ", gzip" : "") +
         ") cannot hold the " + std::to_string(expected) + " bytes of data the sizes need");
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
  if (got < expected) fail("truncated: " + std::to_string(got) + " bytes of data, sizes need " + std::to_string(expected));
  if (gzipped) {
    // zlib checks the stream's trailer (CRC and length) only when asked past the data.
    unsigned char extra = 0;
    int err = Z_OK;
    if (gzread(gz, &extra, 1) < 0 || (gzerror(gz, &err), err != Z_OK)) fail("truncated: the gzip stream ends before its checksum");
  }
  decode(s, swap, raw.data(), count, v.values);
  if (scaled) {
    for (double& x : v.values) x = x * slope + inter;
  }
  placeVolume(path, m, centre0, v);
  return v;
}

// Chessboard distance (in voxels) from each inside voxel to the nearest outside voxel (or the
// volume's edge), by two raster passes over the 26-neighbourhood.
std::vector<int> insideDistance(const std::vector<unsigned char>& inside, glm::ivec3 n) {
  const int big = 1 << 28;
  std::vector<int> d(inside.size());
  const auto idx = [&](int x, int y, int z) { return (std::size_t(z) * n.y + y) * n.x + x; };
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = inside[i] ? big : 0;
  const auto pass = [&](int sign) {
    for (int zz = 0; zz < n.z; ++zz) {
      const int z = sign > 0 ? zz : n.z - 1 - zz;
      for (int yy = 0; yy < n.y; ++yy) {
        const int y = sign > 0 ? yy : n.y - 1 - yy;
        for (int xx = 0; xx < n.x; ++xx) {
          const int x = sign > 0 ? xx : n.x - 1 - xx;
          int& here = d[idx(x, y, z)];
          if (here == 0) continue;
          for (int dz = -1; dz <= 0; ++dz) {
            for (int dy = -1; dy <= 1; ++dy) {
              for (int dx = -1; dx <= 1; ++dx) {
                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                const int nx = x + sign * dx, ny = y + sign * dy, nz = z + sign * dz;
                const int e = (nx < 0 || ny < 0 || nz < 0 || nx >= n.x || ny >= n.y || nz >= n.z)
                                  ? 0 : d[idx(nx, ny, nz)];
                here = std::min(here, e + 1);
              }
            }
          }
        }
      }
    }
  };
  pass(1);
  pass(-1);
  return d;
}

void setGrid(VoxelGrid& grid, const glm::ivec3 n, const std::vector<Fill>& fill, const std::vector<Density>& density) {
  for (int z = 0; z < n.z; ++z) {
    for (int y = 0; y < n.y; ++y) {
      for (int x = 0; x < n.x; ++x) {
        const std::size_t i = (std::size_t(z) * n.y + y) * n.x + x;
        if (fill[i] != 0 || density[i] != 0) grid.set({x, y, z}, fill[i], density[i]);
      }
    }
  }
  grid.clearDirty();
}

}  // namespace

bool isVolumePath(const std::string& path) {
  const std::string p = lower(path);
  return endsWith(p, ".nrrd") || endsWith(p, ".nhdr") || endsWith(p, ".nii") || endsWith(p, ".nii.gz");
}

RawVolume readRawVolume(const std::string& path, bool allowOutsideData) {
  const std::string p = lower(path);
  if (endsWith(p, ".nii") || endsWith(p, ".nii.gz")) return readNiftiVolume(path);
  return readNrrdVolume(path, allowOutsideData);
}

VolumeLoad loadVolume(const std::string& path, const VolumeOptions& options) {
  const std::string p = lower(path);
  const bool nifti = endsWith(p, ".nii") || endsWith(p, ".nii.gz");
  RawVolume raw = readRawVolume(path, options.allowOutsideData);
  VolumeLoad load;
  load.format = nifti ? "nifti" : "nrrd";
  if (raw.osteonGrid) {
    if (options.label || options.isoHu) {
      throw InputError(path + ": an osteon grid (fill and density as saved): " +
                       (options.label ? "--label" : "--iso") + " is for label maps and CTs");
    }
    NrrdReadResult r = readNrrd(path, options.allowOutsideData);
    load.grid = std::move(r.grid);
    load.densityLoaded = r.densityLoaded;
    load.kind = "osteon grid";
    load.type = "fill";
    return load;
  }
  load.type = raw.type;
  const glm::ivec3 n = raw.sizes;
  std::set<double> distinct;
  double lo = raw.values.empty() ? 0.0 : raw.values[0], hi = lo;
  bool whole = true;
  for (double x : raw.values) {
    lo = std::min(lo, x);
    hi = std::max(hi, x);
    if (distinct.size() <= std::size_t(kMaxLabels)) distinct.insert(x);
    if (whole && x != std::floor(x)) whole = false;
  }
  load.minValue = lo;
  load.maxValue = hi;
  const bool labelMap = raw.integer && whole && distinct.size() <= std::size_t(kMaxLabels);
  const bool ct = !labelMap && raw.isSigned && hi - lo >= kMinCtRangeHu;
  try {
    load.grid = VoxelGrid(n, raw.originMm, raw.voxelSizeMm);
  } catch (const std::invalid_argument& e) {
    throw InputError(path + ": " + e.what());
  }
  std::vector<Fill> fill(raw.values.size(), 0);
  std::vector<Density> density(raw.values.size(), 0);
  if (labelMap) {
    if (options.isoHu) {
      throw InputError(path + ": a label map (" + raw.type + ", " + std::to_string(distinct.size()) +
                       " distinct values): --iso is for CTs; use --label");
    }
    load.kind = "label map";
    for (double x : distinct) load.labels.push_back((long long)x);
    if (options.label) {
      if (!distinct.count(double(*options.label))) {
        std::string found;
        for (long long l : load.labels) found += (found.empty() ? "" : ", ") + std::to_string(l);
        throw InputError(path + ": --label " + std::to_string(*options.label) + " is not in the label map (labels found: " +
                         found + ")");
      }
      load.label = options.label;
    }
    std::vector<unsigned char> inside(raw.values.size());
    for (std::size_t i = 0; i < inside.size(); ++i) {
      inside[i] = options.label ? raw.values[i] == double(*options.label) : raw.values[i] != 0.0;
    }
    const std::vector<int> dist = insideDistance(inside, n);
    const int shell = int(std::clamp(std::ceil(options.corticalThicknessMm / raw.voxelSizeMm), 1.0, 1e6));
    for (std::size_t i = 0; i < inside.size(); ++i) {
      if (!inside[i]) continue;
      fill[i] = kFillFull;
      density[i] = dist[i] <= shell ? kCtCorticalDensity : kCtCancellousDensity;
    }
  } else if (ct) {
    if (options.label) {
      throw InputError(path + ": a CT (" + raw.type + ", values " + shortNum(lo) + " to " + shortNum(hi) +
                       "): --label is for label maps; use --iso");
    }
    load.kind = "ct";
    load.isoHu = options.isoHu.value_or(kDefaultIsoHu);
    for (std::size_t i = 0; i < raw.values.size(); ++i) {
      const double t = (raw.values[i] - (load.isoHu - kCtRampHalfWidthHu)) / (2.0 * kCtRampHalfWidthHu);
      const double f = std::clamp(t, 0.0, 1.0);
      fill[i] = Fill(std::lround(f * kFillFull));
      if (fill[i] > 0) density[i] = raw.values[i] >= kCorticalHu ? kCtCorticalDensity : kCtCancellousDensity;
    }
  } else {
    std::ostringstream s;
    s << path << ": neither a label map nor a CT: " << raw.type << ", values " << shortNum(lo) << " to "
      << shortNum(hi) << ", "
      << (distinct.size() > std::size_t(kMaxLabels) ? "more than " + std::to_string(kMaxLabels)
                                                    : std::to_string(distinct.size()))
      << " distinct values (a label map is an integer type with at most " << kMaxLabels
      << " values; a CT a signed type spanning at least " << kMinCtRangeHu << " HU)";
    throw InputError(s.str());
  }
  setGrid(load.grid, n, fill, density);
  return load;
}

}  // namespace osteon::geometry
