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
#include "osteon/core/input_file.h"
#include "osteon/core/memory.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/io/mesh_io.h"

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

// A scalar type: its name, width and how to read one value.
struct Scalar {
  std::string name;
  std::size_t bytes = 0;
  bool integer = true;
  bool isSigned = false;
};

std::optional<Scalar> nrrdScalar(const std::string& typeText) {
  std::string t;
  for (unsigned char c : trim(typeText)) {
    if (std::isspace(c)) {
      if (!t.empty() && t.back() != ' ') t += ' ';
    } else {
      t += char(std::tolower(c));
    }
  }
  static const std::map<std::string, Scalar> types = {
      {"signed char", {"int8", 1, true, true}},   {"int8", {"int8", 1, true, true}},
      {"int8_t", {"int8", 1, true, true}},        {"uchar", {"uint8", 1, true, false}},
      {"unsigned char", {"uint8", 1, true, false}}, {"uint8", {"uint8", 1, true, false}},
      {"uint8_t", {"uint8", 1, true, false}},     {"short", {"int16", 2, true, true}},
      {"short int", {"int16", 2, true, true}},    {"signed short", {"int16", 2, true, true}},
      {"signed short int", {"int16", 2, true, true}}, {"int16", {"int16", 2, true, true}},
      {"int16_t", {"int16", 2, true, true}},      {"ushort", {"uint16", 2, true, false}},
      {"unsigned short", {"uint16", 2, true, false}}, {"unsigned short int", {"uint16", 2, true, false}},
      {"uint16", {"uint16", 2, true, false}},     {"uint16_t", {"uint16", 2, true, false}},
      {"int", {"int32", 4, true, true}},          {"signed int", {"int32", 4, true, true}},
      {"int32", {"int32", 4, true, true}},        {"int32_t", {"int32", 4, true, true}},
      {"uint", {"uint32", 4, true, false}},       {"unsigned int", {"uint32", 4, true, false}},
      {"uint32", {"uint32", 4, true, false}},     {"uint32_t", {"uint32", 4, true, false}},
      {"longlong", {"int64", 8, true, true}},     {"long long", {"int64", 8, true, true}},
      {"long long int", {"int64", 8, true, true}}, {"signed long long", {"int64", 8, true, true}},
      {"signed long long int", {"int64", 8, true, true}}, {"int64", {"int64", 8, true, true}},
      {"int64_t", {"int64", 8, true, true}},      {"ulonglong", {"uint64", 8, true, false}},
      {"unsigned long long", {"uint64", 8, true, false}},
      {"unsigned long long int", {"uint64", 8, true, false}}, {"uint64", {"uint64", 8, true, false}},
      {"uint64_t", {"uint64", 8, true, false}},   {"float", {"float", 4, false, true}},
      {"double", {"double", 8, false, true}},
  };
  const auto it = types.find(t);
  if (it == types.end()) return std::nullopt;
  return it->second;
}

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

std::vector<unsigned char> readFileBytes(const std::string& path, std::uint64_t offset) {
  requireInputFile(path);
  std::error_code ec;
  const std::uint64_t size = fs::file_size(path, ec);
  if (ec) throw InputError(path + ": cannot read its size");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
  if (offset > size) throw InputError(path + ": truncated (no data after the header)");
  std::vector<unsigned char> bytes(size - offset);
  in.seekg(std::streamoff(offset));
  if (!bytes.empty() && !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()))) {
    throw InputError(path + ": read failed");
  }
  return bytes;
}

// A volume is read as its stored values, then decoded to doubles, then made a grid (fill and
// density per voxel): a size past the machine's memory is refused before any of it is allocated.
void refuseOverVolumeMemory(const std::string& path, glm::ivec3 sizes, int scalarBytes) {
  const double voxels = double(sizes.x) * sizes.y * sizes.z;
  refuseOverMemory(path + ": a " + std::to_string(sizes.x) + " x " + std::to_string(sizes.y) + " x " +
                       std::to_string(sizes.z) + " volume",
                   voxels * double(scalarBytes + sizeof(double) + sizeof(std::uint16_t) + sizeof(std::int16_t)), "");
}

// Inflates gzip (or zlib) data that must hold exactly `expected` bytes.
// deflate never compresses more than about 1032:1: more than that is a lie, refused unallocated.
constexpr std::uint64_t kMaxDeflateRatio = 1032;

void checkDeflateRatio(const std::string& path, std::size_t gzipBytes, std::uint64_t expected) {
  if (expected > std::uint64_t(gzipBytes) * kMaxDeflateRatio + 1024) {
    throw InputError(path + ": truncated: " + std::to_string(gzipBytes) + " bytes of gzip data cannot hold the " +
                     std::to_string(expected) + " bytes the sizes need");
  }
}

std::vector<unsigned char> inflateExactly(const std::string& path, const std::vector<unsigned char>& in,
                                          std::uint64_t expected) {
  checkDeflateRatio(path, in.size(), expected);
  std::vector<unsigned char> out(expected);
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) throw InputError(path + ": zlib failed to start");
  z.next_in = const_cast<unsigned char*>(in.data());
  z.avail_in = uInt(std::min<std::size_t>(in.size(), 0x7fffffff));
  z.next_out = out.data();
  z.avail_out = uInt(std::min<std::uint64_t>(expected, 0x7fffffff));
  int rc = Z_OK;
  while (rc == Z_OK) {
    rc = inflate(&z, Z_NO_FLUSH);
    if (rc == Z_OK && z.avail_out == 0) {
      const std::uint64_t done = z.total_out;
      if (done >= expected) {
        unsigned char extra;
        z.next_out = &extra;
        z.avail_out = 1;
        rc = inflate(&z, Z_NO_FLUSH);
        if (z.avail_out == 0) {
          inflateEnd(&z);
          throw InputError(path + ": gzip data is longer than the sizes need (" +
                           std::to_string(expected) + " bytes)");
        }
        if (rc != Z_STREAM_END) {  // the data is whole but its trailer (checksum, length) is not
          inflateEnd(&z);
          throw InputError(path + ": truncated: the gzip stream ends before its checksum");
        }
        break;
      }
      z.avail_out = uInt(std::min<std::uint64_t>(expected - done, 0x7fffffff));
    }
  }
  const std::uint64_t got = z.total_out;
  inflateEnd(&z);
  if (rc != Z_STREAM_END && rc != Z_OK && rc != Z_BUF_ERROR) {
    throw InputError(path + ": gzip data is corrupt (" + (z.msg ? z.msg : "zlib error") + ")");
  }
  if (got < expected) {
    throw InputError(path + ": truncated: " + std::to_string(got) + " bytes of gzip data, sizes need " +
                     std::to_string(expected));
  }
  return out;
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

RawVolume readNrrdVolume(const std::string& path) {
  const auto fail = [&path](const std::string& reason) { throw InputError(path + ": " + reason); };
  requireInputFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open (" + std::string(std::strerror(errno)) + ")");
  std::string line;
  // Lines bounded at 64 KiB: a binary file or a runaway comment is refused, not read whole.
  const auto readLine = [&in, &line]() {
    line.clear();
    for (int c; (c = in.get()) != EOF;) {
      if (c == '\n') return true;
      line += char(c);
      if (line.size() > 65536) return true;
    }
    return !line.empty();
  };
  readLine();
  if (line.compare(0, 7, "NRRD000") != 0) fail("not a NRRD file (no NRRD000x magic)");
  // NRRD0001 to NRRD0005 are the versions there are; a later one may mean what this reader cannot.
  if (line.size() < 8 || line[7] < '1' || line[7] > '5') fail(excerpt(line) + " is not a NRRD version this reader knows (NRRD0001 to NRRD0005)");
  std::size_t lineNo = 1;
  std::map<std::string, std::string> fields;
  bool osteon = false;
  bool ended = false;
  while (readLine()) {
    ++lineNo;
    if (line.size() > 65536) fail("header line " + std::to_string(lineNo) + " is longer than 64 KiB (not a text header?)");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) {
      ended = true;
      break;
    }
    if (line[0] == '#') {
      if (line.rfind("# osteon voxel grid", 0) == 0) osteon = true;
      continue;
    }
    const std::size_t kv = line.find(":=");
    const std::size_t colon = line.find(": ");
    if (kv != std::string::npos && (colon == std::string::npos || kv < colon)) {
      if (line.rfind("osteon_", 0) == 0) osteon = true;
      continue;
    }
    if (colon == std::string::npos) fail("malformed header line " + excerpt(line));
    std::string name;
    for (unsigned char c : line.substr(0, colon)) {
      if (!std::isspace(c)) name += char(std::tolower(c));
    }
    fields[name] = trim(line.substr(colon + 2));
  }
  RawVolume v;
  if (osteon) {
    v.osteonGrid = true;
    return v;
  }
  const auto field = [&](const char* name) -> const std::string* {
    const auto it = fields.find(name);
    return it == fields.end() ? nullptr : &it->second;
  };
  const auto require = [&](const char* name, const char* shown) -> const std::string& {
    const std::string* f = field(name);
    if (!f) fail(std::string("missing '") + shown + "' field");
    return *f;
  };
  const std::string* dataFile = field("datafile");
  if (!dataFile) dataFile = field("data_file");
  if (!ended && !dataFile) fail("header is not ended by a blank line (no data?)");
  if (trim(require("dimension", "dimension")) != "3") fail("dimension " + excerpt(*field("dimension")) + " is not supported (need 3)");
  const std::string typeText = require("type", "type");
  const std::optional<Scalar> scalar = nrrdScalar(typeText);
  if (!scalar) fail("type " + excerpt(typeText) + " is not a NRRD scalar type");
  v.type = scalar->name;
  v.integer = scalar->integer;
  v.isSigned = scalar->isSigned;
  const std::string encoding = lower(trim(require("encoding", "encoding")));
  const bool gzip = encoding == "gzip" || encoding == "gz";
  if (!gzip && encoding != "raw") fail("encoding " + excerpt(encoding) + " is not supported (raw or gzip)");
  bool bigEndian = false;
  if (const std::string* e = field("endian")) {
    const std::string s = lower(trim(*e));
    if (s != "little" && s != "big") fail("endian " + excerpt(s) + " is not little or big");
    bigEndian = s == "big";
  } else if (scalar->bytes > 1) {
    fail("missing 'endian' field (required for multi-byte data)");
  }
  std::vector<double> sizes;
  if (!parseNumbers(require("sizes", "sizes"), sizes) || sizes.size() != 3) fail("sizes are not three integers");
  v.sizes = checkSizes(path, sizes);
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
    const std::string dataPath =
        dataFile ? (fs::path(path).parent_path() / fs::path(trim(*dataFile))).string() : path;
    const std::uint64_t count = std::uint64_t(v.sizes.x) * v.sizes.y * v.sizes.z;
    const std::uint64_t expected = count * scalar->bytes;
    std::vector<unsigned char> raw;
    if (dataFile) {
      const std::string d = trim(*dataFile);
      if (d.rfind("LIST", 0) == 0 || d.find('%') != std::string::npos || d.find(' ') != std::string::npos) {
        fail("data file " + excerpt(d) + ": only a single data file is supported");
      }
      try {
        raw = readFileBytes(dataPath, 0);
      } catch (const InputError& e) {
        throw InputError(path + ": data file " + e.what());  // the header is the file the user named
      }
    } else {
      raw = readFileBytes(path, std::uint64_t(in.tellg()));
    }
    const std::string shown = dataFile ? path + ": data file " + dataPath : path;
    // A file that cannot hold its sizes is told as truncated, before what the sizes would cost.
    if (gzip) {
      checkDeflateRatio(shown, raw.size(), expected);
    } else if (raw.size() != expected) {
      throw InputError(shown + ": " + (raw.size() < expected ? "truncated: " : "") + std::to_string(raw.size()) +
                       " bytes of data, sizes need " + std::to_string(expected));
    }
    refuseOverVolumeMemory(path, v.sizes, scalar->bytes);
    if (gzip) raw = inflateExactly(shown, raw, expected);
    decode(*scalar, bigEndian, raw.data(), count, v.values);
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
  std::error_code ec;
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
  if (!ec && expected > (gzipped ? fileBytes * kMaxDeflateRatio + 1024 : fileBytes)) {
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

RawVolume readRawVolume(const std::string& path) {
  const std::string p = lower(path);
  if (endsWith(p, ".nii") || endsWith(p, ".nii.gz")) return readNiftiVolume(path);
  return readNrrdVolume(path);
}

VolumeLoad loadVolume(const std::string& path, const VolumeOptions& options) {
  const std::string p = lower(path);
  const bool nifti = endsWith(p, ".nii") || endsWith(p, ".nii.gz");
  RawVolume raw = readRawVolume(path);
  VolumeLoad load;
  load.format = nifti ? "nifti" : "nrrd";
  if (raw.osteonGrid) {
    if (options.label || options.isoHu) {
      throw InputError(path + ": an osteon grid (fill and density as saved): " +
                       (options.label ? "--label" : "--iso") + " is for label maps and CTs");
    }
    NrrdReadResult r = readNrrd(path);
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
