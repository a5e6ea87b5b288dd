#include "io/nrrd_header.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "osteon/core/error.h"
#include "osteon/core/input_file.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry::nrrd {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxHeaderLine = 65536;

bool parseSizes(const std::string& text, std::vector<double>& values) {
  values.clear();
  for (const std::string& w : words(text)) {
    double v;
    if (!parseNumber(w, v)) return false;
    values.push_back(v);
  }
  return true;
}

// One header line, at most kMaxHeaderLine bytes; false at the end of the file with nothing read.
enum class LineRead { Line, LastLine, End, TooLong };
LineRead readLine(std::istream& in, std::string& line, std::uint64_t& consumed) {
  line.clear();
  for (int c; (c = in.get()) != EOF;) {
    ++consumed;
    if (c == '\n') return LineRead::Line;
    line += static_cast<char>(c);
    if (line.size() > kMaxHeaderLine) return LineRead::TooLong;  // not a text header
  }
  return line.empty() ? LineRead::End : LineRead::LastLine;
}

// A name for a field as the NRRD format spells its variants: "data file", "datafile",
// "data_file" are one field, so a header cannot give it twice under two spellings.
std::string fieldName(const std::string& text) {
  std::string name;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (!std::isspace(c) && c != '_') name += static_cast<char>(std::tolower(c));
  }
  return name;
}

}  // namespace

[[noreturn]] void failAt(const std::string& shown, const std::string& reason) {
  throw InputError(shown + ": " + reason);
}

// Every loader's check of a name (core/input_file.h), with the name as this reader shows it.
void checkRegularFile(const std::string& path, const std::string& shown) {
  const std::string problem = inputFileProblem(path);
  if (!problem.empty()) failAt(printableFileName(shown), problem);
}

const std::string* Header::field(const char* name) const {
  const auto it = fields.find(name);
  return it == fields.end() ? nullptr : &it->second;
}

const std::string& Header::require(const char* name, const char* shown) const {
  const std::string* v = field(name);
  if (!v) fail(std::string("missing '") + shown + "' field");
  return *v;
}

void Header::fail(const std::string& reason) const {
  throw InputError(path + ": " + reason);
}

Header readHeader(const std::string& path) {
  Header h;
  h.path = path;
  checkRegularFile(path, path);
  std::ifstream in(path, std::ios::binary);
  if (!in) h.fail("cannot open (" + std::string(std::strerror(errno)) + ")");

  std::string line;
  std::uint64_t consumed = 0;
  const LineRead first = readLine(in, line, consumed);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (first == LineRead::End || line.compare(0, 7, "NRRD000") != 0)
    h.fail("not a NRRD file (no NRRD000x magic)");
  // NRRD0001 to NRRD0005 are the versions there are; a later one may mean what this reader cannot.
  if (line.size() != 8 || line[7] < '1' || line[7] > '5') {
    h.fail(excerpt(line) + " is not a NRRD version this reader knows (NRRD0001 to NRRD0005)");
  }
  std::map<std::string, std::size_t> fieldLine;  // where each field was given
  std::map<std::string, std::size_t> keyLine;
  for (std::size_t lineNo = 2;; ++lineNo) {
    const LineRead read = readLine(in, line, consumed);
    if (read == LineRead::TooLong) {
      h.fail("header line " + std::to_string(lineNo) +
             " is longer than 64 KiB (not a text header?)");
    }
    if (read == LineRead::End) break;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) {
      h.ended = true;
      break;
    }
    if (line[0] == '#') {
      h.comments.push_back(line.substr(1));
    } else {
      const std::size_t kv = line.find(":=");
      const std::size_t colon = line.find(": ");
      const bool isKey = kv != std::string::npos && (colon == std::string::npos || kv < colon);
      if (!isKey && colon == std::string::npos) h.fail("malformed header line " + excerpt(line));
      // The format allows each field and key once; which of two a reader keeps is anyone's guess.
      const std::string name = isKey ? line.substr(0, kv) : fieldName(line.substr(0, colon));
      std::map<std::string, std::size_t>& seen = isKey ? keyLine : fieldLine;
      if (const auto it = seen.find(name); it != seen.end()) {
        h.fail(std::string(isKey ? "key " : "field ") +
               excerpt(trim(line.substr(0, isKey ? kv : colon))) + " given twice (header lines " +
               std::to_string(it->second) + " and " + std::to_string(lineNo) + ")");
      }
      seen[name] = lineNo;
      if (isKey) {
        h.keys[name] = line.substr(kv + 2);
      } else {
        h.fields[name] = trim(line.substr(colon + 2));
        // "data file: LIST": the header's remaining lines are file names, not fields.
        if (name == "datafile" && h.fields[name].rfind("LIST", 0) == 0) break;
      }
    }
    if (read == LineRead::LastLine) break;
  }
  h.headerBytes = consumed;
  if (!h.ended && !h.field("datafile")) h.fail("header is not ended by a blank line (no data?)");
  return h;
}

OsteonFile osteonFile(const Header& h) {
  if (!h.keys.count("osteon_voxel_size_mm") || !h.keys.count("osteon_origin_mm"))
    return OsteonFile::None;
  for (const std::string& c : h.comments) {
    if (c.rfind(" osteon voxel grid: fill, ", 0) == 0) return OsteonFile::Fill;
    if (c.rfind(" osteon voxel grid: density", 0) == 0) return OsteonFile::Density;
  }
  return OsteonFile::None;
}

glm::ivec3 readSizes(const Header& h) {
  const std::string& dimension = h.require("dimension", "dimension");
  if (trim(dimension) != "3")
    h.fail("dimension " + excerpt(dimension) + " is not supported (need 3)");
  std::vector<double> sizes;
  const std::string& sizesText = h.require("sizes", "sizes");
  if (!parseSizes(sizesText, sizes) || sizes.size() != 3) {
    h.fail("sizes " + excerpt(sizesText) + " are not three integers");
  }
  glm::ivec3 n;
  std::uint64_t voxels = 1;
  for (int a = 0; a < 3; ++a) {
    const double size = sizes[std::size_t(a)];
    if (!(size >= 1 && size <= double(1 << 30) && size == std::floor(size))) {
      h.fail("sizes " + excerpt(sizesText) + " are not three integers from 1 to 2^30");
    }
    n[a] = int(size);
    voxels *= std::uint64_t(n[a]);
    if (voxels > VoxelGrid::kMaxVoxels)
      h.fail("sizes " + excerpt(sizesText) + " exceed 2^32 voxels");
  }
  // A colour or vector axis holds components of one sample, not positions in space.
  if (const std::string* kinds = h.field("kinds")) {
    const std::vector<std::string> k = words(*kinds);
    if (k.size() != 3) h.fail("kinds " + excerpt(*kinds) + " are not three (one per axis)");
    for (int a = 0; a < 3; ++a) {
      const std::string& word = k[std::size_t(a)];
      const std::string kind = normaliseWords(word);
      if (kind != "domain" && kind != "space" && kind != "???" && kind != "none") {
        h.fail("kinds " + excerpt(*kinds) + ": axis " + std::to_string(a) + " is " + excerpt(word) +
               ", not a spatial axis (only domain, space or ??? axes; colour, vector and list "
               "volumes are "
               "not supported)");
      }
    }
  }
  return n;
}

std::optional<Scalar> scalarNamed(const std::string& typeText) {
  static const std::map<std::string, Scalar> types = {
      {"signed char", {"int8", 1, true, true}},
      {"int8", {"int8", 1, true, true}},
      {"int8_t", {"int8", 1, true, true}},
      {"uchar", {"uint8", 1, true, false}},
      {"unsigned char", {"uint8", 1, true, false}},
      {"uint8", {"uint8", 1, true, false}},
      {"uint8_t", {"uint8", 1, true, false}},
      {"short", {"int16", 2, true, true}},
      {"short int", {"int16", 2, true, true}},
      {"signed short", {"int16", 2, true, true}},
      {"signed short int", {"int16", 2, true, true}},
      {"int16", {"int16", 2, true, true}},
      {"int16_t", {"int16", 2, true, true}},
      {"ushort", {"uint16", 2, true, false}},
      {"unsigned short", {"uint16", 2, true, false}},
      {"unsigned short int", {"uint16", 2, true, false}},
      {"uint16", {"uint16", 2, true, false}},
      {"uint16_t", {"uint16", 2, true, false}},
      {"int", {"int32", 4, true, true}},
      {"signed int", {"int32", 4, true, true}},
      {"int32", {"int32", 4, true, true}},
      {"int32_t", {"int32", 4, true, true}},
      {"uint", {"uint32", 4, true, false}},
      {"unsigned int", {"uint32", 4, true, false}},
      {"uint32", {"uint32", 4, true, false}},
      {"uint32_t", {"uint32", 4, true, false}},
      {"longlong", {"int64", 8, true, true}},
      {"long long", {"int64", 8, true, true}},
      {"long long int", {"int64", 8, true, true}},
      {"signed long long", {"int64", 8, true, true}},
      {"signed long long int", {"int64", 8, true, true}},
      {"int64", {"int64", 8, true, true}},
      {"int64_t", {"int64", 8, true, true}},
      {"ulonglong", {"uint64", 8, true, false}},
      {"unsigned long long", {"uint64", 8, true, false}},
      {"unsigned long long int", {"uint64", 8, true, false}},
      {"uint64", {"uint64", 8, true, false}},
      {"uint64_t", {"uint64", 8, true, false}},
      {"float", {"float", 4, false, true}},
      {"double", {"double", 8, false, true}},
  };
  const auto it = types.find(normaliseWords(typeText));
  if (it == types.end()) return std::nullopt;
  return it->second;
}

Layout readLayout(const Header& h) {
  Layout layout;
  const std::string& typeText = h.require("type", "type");
  const std::optional<Scalar> scalar = scalarNamed(typeText);
  if (!scalar) h.fail("type " + excerpt(typeText) + " is not a NRRD scalar type");
  layout.scalar = *scalar;
  const std::string encoding = normaliseWords(h.require("encoding", "encoding"));
  layout.gzip = encoding == "gzip" || encoding == "gz";
  if (!layout.gzip && encoding != "raw")
    h.fail("encoding " + excerpt(encoding) + " is not supported (raw or gzip)");
  if (const std::string* e = h.field("endian")) {
    const std::string s = normaliseWords(*e);
    if (s != "little" && s != "big") h.fail("endian " + excerpt(s) + " is not little or big");
    layout.bigEndian = s == "big";
  } else if (scalar->bytes > 1) {
    h.fail("missing 'endian' field (required for multi-byte data)");
  }
  return layout;
}

}  // namespace osteon::geometry::nrrd
