#include "preflight.h"

#include "osteon/geometry/error.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

namespace osteon::geometry::detail {
namespace {

std::string readPrefix(const std::string& path, std::size_t maxBytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  std::string bytes(maxBytes, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(maxBytes));
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  return bytes;
}

bool looksLikeText(const std::string& bytes) {
  for (unsigned char c : bytes) {
    const bool whitespace = c >= 0x09 && c <= 0x0d;
    if (!whitespace && (c < 0x20 || c > 0x7e)) return false;
  }
  return true;
}

bool startsWithNoCase(const std::string& s, const char* prefix) {
  const std::size_t n = std::strlen(prefix);
  if (s.size() < n) return false;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::tolower(static_cast<unsigned char>(s[i])) != prefix[i]) return false;
  }
  return true;
}

}  // namespace

StlKind preflightStl(const std::string& path, std::uint64_t fileBytes) {
  const std::string head = readPrefix(path, 4096);
  const bool solidPrefix = startsWithNoCase(head, "solid");
  if (fileBytes < 84) {
    if (solidPrefix && looksLikeText(head)) return StlKind::Ascii;
    throw InputError(path + ": too short for a binary STL (" + std::to_string(fileBytes) +
                     " bytes, the header alone is 84)");
  }
  std::uint32_t count = 0;
  std::memcpy(&count, head.data() + 80, sizeof(count));  // little-endian, as x86 stores it
  const std::uint64_t expected = 84 + 50 * std::uint64_t(count);
  // The size law wins over the "solid" prefix: CAD exporters write "solid" into binary
  // headers, and an ASCII file matching the law byte for byte would be a remarkable accident.
  if (expected == fileBytes && !(solidPrefix && looksLikeText(head))) return StlKind::Binary;
  if (solidPrefix && looksLikeText(head)) return StlKind::Ascii;

  constexpr std::uint64_t kMaxCount = (std::numeric_limits<std::uint32_t>::max() - 84) / 50;
  if (count > kMaxCount) {
    throw InputError(path + ": binary STL triangle count " + std::to_string(count) +
                     " overflows 32-bit arithmetic (84 + 50 n = " + std::to_string(expected) +
                     " bytes > 4 GiB; the file has " + std::to_string(fileBytes) + ")");
  }
  std::ostringstream msg;
  msg << path << ": " << (fileBytes < expected ? "truncated" : "oversized")
      << " binary STL: " << fileBytes << " bytes, but its header's " << count
      << " triangles need 84 + 50 n = " << expected;
  throw InputError(msg.str());
}

bool preflightOff(const std::string& path, std::uint64_t fileBytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  std::string firstLine;
  std::getline(in, firstLine);
  const bool binary = firstLine.find("BINARY") != std::string::npos;
  if (firstLine.find("OFF") == std::string::npos) {
    throw InputError(path + ": not an OFF file (first line lacks the OFF keyword)");
  }
  // Counts follow on the first non-comment line (some writers put them on the OFF line).
  std::string rest = firstLine.substr(firstLine.find("OFF") + 3);
  if (binary) rest = rest.substr(rest.find("BINARY") + 6);
  std::string line = rest;
  while (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t\r")] == '#') {
    if (!std::getline(in, line)) throw InputError(path + ": OFF header has no element counts");
  }
  std::istringstream counts(line);
  long long vertices = -1;
  long long faces = -1;
  counts >> vertices >> faces;
  if (!counts || vertices < 0 || faces < 0) {
    throw InputError(path + ": OFF header counts are missing or negative: '" + line + "'");
  }
  // Smallest possible records: ASCII "0 0 0\n" and "3 0 1 2\n"; binary 3 floats and 4 ints.
  const long double need = binary ? 12.0L * vertices + 16.0L * faces
                                  : 6.0L * vertices + 8.0L * faces;
  if (need > static_cast<long double>(fileBytes)) {
    throw InputError(path + ": OFF header promises " + std::to_string(vertices) +
                     " vertices and " + std::to_string(faces) + " faces, more than its " +
                     std::to_string(fileBytes) + " bytes can hold (truncated file?)");
  }
  return binary;
}

namespace {

int plyTypeBytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" ||
      type == "float" || type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return -1;
}

}  // namespace

bool preflightPly(const std::string& path, std::uint64_t fileBytes) {
  // OpenMesh's PLY reader trusts its header (malformed ones crash it or send it looping), so
  // the header is checked here in full: known keywords only, a known format, typed
  // properties under an element, a vertex element with x, y and z.
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  std::string line;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != "ply") throw InputError(path + ": not a PLY file (no 'ply' magic)");
  const auto bad = [&](std::size_t lineNo, const std::string& why) {
    return InputError(path + ": PLY header line " + std::to_string(lineNo) + ": " + why);
  };
  bool binary = false;
  bool formatSeen = false;
  bool inElement = false;
  std::string element;
  int vertexXyz = 0;
  bool vertexSeen = false;
  long double needBytes = 0.0L;
  long double elementCount = 0.0L;
  long double recordBytes = 0.0L;
  auto closeElement = [&] { needBytes += elementCount * recordBytes; };
  std::size_t lineNo = 1;
  while (std::getline(in, line)) {
    if (++lineNo > 10000) throw InputError(path + ": PLY header has no end_header");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    for (unsigned char c : line) {
      if (c < 0x20 || c > 0x7e) throw bad(lineNo, "non-printable byte in the header");
    }
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      std::string kind, version, extra;
      words >> kind >> version;
      if (words >> extra || version != "1.0" ||
          (kind != "ascii" && kind != "binary_little_endian" && kind != "binary_big_endian")) {
        throw bad(lineNo, "unknown format '" + line + "'");
      }
      binary = kind != "ascii";
      formatSeen = true;
    } else if (keyword == "element") {
      closeElement();
      long long count = -1;
      std::string extra;
      words >> element >> count;
      if (!words || count < 0 || (words >> extra)) throw bad(lineNo, "bad element line '" + line + "'");
      inElement = true;
      vertexSeen = vertexSeen || element == "vertex";
      elementCount = static_cast<long double>(count);
      recordBytes = 0.0L;
    } else if (keyword == "property") {
      if (!inElement) throw bad(lineNo, "property before any element");
      std::string type, name, extra;
      words >> type;
      if (type == "list") {
        std::string countType, itemType;
        words >> countType >> itemType >> name;
        const int bytes = plyTypeBytes(countType);
        if (bytes < 0 || plyTypeBytes(itemType) < 0 || name.empty() || (words >> extra)) {
          throw bad(lineNo, "bad list property '" + line + "'");
        }
        recordBytes += binary ? bytes : 2;
      } else {
        words >> name;
        const int bytes = plyTypeBytes(type);
        if (bytes < 0 || name.empty() || (words >> extra)) {
          throw bad(lineNo, "bad property '" + line + "'");
        }
        recordBytes += binary ? bytes : 2;
        if (element == "vertex" && (name == "x" || name == "y" || name == "z")) ++vertexXyz;
      }
    } else if (keyword == "end_header") {
      closeElement();
      if (!formatSeen) throw InputError(path + ": PLY header has no format line");
      if (!vertexSeen || vertexXyz != 3) {
        throw InputError(path + ": PLY header has no vertex element with x, y and z");
      }
      const auto headerEnd = static_cast<std::uint64_t>(in.tellg());
      if (needBytes > static_cast<long double>(fileBytes - headerEnd)) {
        throw InputError(path + ": PLY header promises more elements than its " +
                         std::to_string(fileBytes) + " bytes can hold (truncated file?)");
      }
      return binary;
    } else {
      throw bad(lineNo, "unknown keyword '" + keyword + "'");
    }
  }
  throw InputError(path + ": PLY header has no end_header");
}

void checkBinaryStlFinite(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  in.seekg(84);
  char record[50];
  for (std::uint64_t tri = 0; in.read(record, sizeof(record)); ++tri) {
    float coords[9];
    std::memcpy(coords, record + 12, sizeof(coords));  // skip the facet normal
    for (int k = 0; k < 9; ++k) {
      if (!std::isfinite(coords[k])) {
        throw InputError(path + ": triangle " + std::to_string(tri) + " has a non-finite vertex coordinate (" +
                         std::to_string(coords[k]) + ")");
      }
    }
  }
}

void checkTextCoordinatesFinite(const std::string& path, const std::string& format) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  // Which lines carry coordinates: OBJ "v", STL "vertex", OFF/PLY every line of the body.
  bool inBody = format == "obj" || format == "stl";
  bool offCountsPending = format == "off";
  std::string line;
  std::size_t lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    std::istringstream words(line);
    std::string first;
    if (!(words >> first) || first[0] == '#') continue;
    if (!inBody) {
      if (format == "ply" && first == "end_header") inBody = true;
      if (format == "off" && first.find("OFF") != std::string::npos) inBody = true;
      continue;
    }
    if (format == "obj" && first != "v") continue;
    if (format == "stl" && first != "vertex") continue;
    if (offCountsPending) {  // the counts line of an OFF file holds no coordinates
      offCountsPending = false;
      continue;
    }
    std::string token = (format == "obj" || format == "stl") ? std::string() : first;
    do {
      if (token.empty()) continue;
      char* end = nullptr;
      const double value = std::strtod(token.c_str(), &end);
      if (end != token.c_str() && !std::isfinite(value)) {
        throw InputError(path + ": line " + std::to_string(lineNo) +
                         " has a non-finite coordinate '" + token + "'");
      }
    } while (words >> token);
  }
}

}  // namespace osteon::geometry::detail
