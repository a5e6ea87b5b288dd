#include "preflight.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#include "osteon/core/error.h"
#include "text_scan.h"

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

// Text: no control bytes but whitespace (UTF-8 names and comments are fine).
bool looksLikeText(const std::string& bytes) {
  for (const char ch : bytes) {
    const auto c = static_cast<unsigned char>(ch);
    const bool whitespace = c >= 0x09 && c <= 0x0d;
    if (!whitespace && (c < 0x20 || c == 0x7f)) return false;
  }
  return true;
}

// The text after a UTF-8 byte-order mark and leading whitespace.
std::string skipLead(const std::string& s) {
  std::size_t i = s.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return s.substr(i);
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
  const bool solidPrefix = startsWithNoCase(skipLead(head), "solid");
  // Text that breaks the rules (a control byte, no "solid", NUL padding) is still text: the
  // ASCII check then names the flaw instead of a binary count read from its characters.
  const bool text = (solidPrefix && looksLikeText(head)) || looksLikeAsciiStl(head);
  if (fileBytes < 84) {
    if (text) return StlKind::Ascii;
    throw InputError(path + ": too short for a binary STL (" + std::to_string(fileBytes) +
                     " bytes, the header alone is 84)");
  }
  std::uint32_t count = 0;
  std::memcpy(&count, head.data() + 80, sizeof(count));  // little-endian, as x86 stores it
  const std::uint64_t expected = 84 + 50 * std::uint64_t(count);
  // The size law wins over the "solid" prefix: CAD exporters write "solid" into binary
  // headers, and an ASCII file matching the law byte for byte would be a remarkable accident.
  if (expected == fileBytes && !(solidPrefix && looksLikeText(head))) return StlKind::Binary;
  if (text) return StlKind::Ascii;

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

namespace {

int plyTypeBytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return -1;
}

bool plyTypeIsFloat(const std::string& type) {
  return type == "float" || type == "float32" || type == "double" || type == "float64";
}

std::pair<long long, long long> plyIntegerRange(const std::string& type) {
  const bool isUnsigned = type[0] == 'u';
  const int bits = 8 * plyTypeBytes(type);
  if (isUnsigned) return {0, (1LL << bits) - 1};
  return {-(1LL << (bits - 1)), (1LL << (bits - 1)) - 1};
}

struct PlyProperty {
  std::string name;
  bool list = false;
  bool coordinate = false;  // vertex x, y or z
  std::string countType;    // list only
  std::string type;         // scalar type, or the list's item type
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

// Reads an unsigned list count of `type` from binary bytes.
std::uint64_t readCount(const unsigned char* p, const std::string& type, bool bigEndian) {
  const int n = plyTypeBytes(type);
  std::uint64_t v = 0;
  for (int b = 0; b < n; ++b) {
    const int shift = 8 * (bigEndian ? n - 1 - b : b);
    v |= std::uint64_t(p[b]) << shift;
  }
  if (type[0] != 'u' && n < 8 && (v >> (8 * n - 1)) != 0) return ~std::uint64_t(0);  // negative
  return v;
}

// Walks the body record by record as the header describes it, so no list count can send the
// parser past the end of the file: binary counts must fit the bytes left, ASCII counts the
// tokens left; ASCII values must be numbers of their declared type, floats finite.
void checkBinaryPlyBody(const std::string& path, std::ifstream& in, bool bigEndian,
                        const std::vector<PlyElement>& elements) {
  const std::string body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto* bytes = reinterpret_cast<const unsigned char*>(body.data());
  std::uint64_t at = 0;
  const std::uint64_t size = body.size();
  for (const PlyElement& e : elements) {
    for (long long r = 0; r < e.count; ++r) {
      for (const PlyProperty& p : e.properties) {
        if (!p.list) {
          at += std::uint64_t(plyTypeBytes(p.type));
          continue;
        }
        const int countBytes = plyTypeBytes(p.countType);
        if (at + std::uint64_t(countBytes) > size) break;
        const std::uint64_t n = readCount(bytes + at, p.countType, bigEndian);
        if (n > std::uint64_t(kMaxCorners)) {
          throw InputError(path + ": element '" + e.name + "' record " + std::to_string(r) +
                           " has a list of " + std::to_string(n) + " items (corrupt count?)");
        }
        at += std::uint64_t(countBytes) + n * std::uint64_t(plyTypeBytes(p.type));
      }
      if (at > size) {
        throw InputError(path + ": truncated PLY: element '" + e.name + "' record " +
                         std::to_string(r) + " runs past the end of the file");
      }
    }
  }
  // More data than the header describes means header and data disagree (a wrong count or
  // type); a trailing newline some writers add is not data.
  const std::size_t extra = std::size_t(size - at);
  if (extra > 2 || body.find_first_not_of("\r\n", std::size_t(at)) != std::string::npos) {
    throw InputError(path + ": binary PLY has " + std::to_string(extra) +
                     " bytes after the elements its header describes (wrong count or type?)");
  }
}

void checkAsciiPlyBody(const std::string& path, std::ifstream& in, std::size_t headerLines,
                       const std::vector<PlyElement>& elements) {
  // ASCII: once a token fails OpenMesh's stream extraction, its reader loops over every count
  // and list length that follows unread; so each value must be a number of its declared type.
  TokenReader tokens(in, headerLines);
  std::string_view token;
  for (const PlyElement& e : elements) {
    for (long long r = 0; r < e.count; ++r) {
      const auto where = [&] {
        return path + ": line " + std::to_string(tokens.lineNo()) + ": element '" + e.name +
               "' record " + std::to_string(r);
      };
      const auto next = [&] {
        if (!tokens.next(token)) {
          throw InputError(where() + ": truncated PLY: the element runs past the end of the file");
        }
      };
      const auto checkValue = [&](const PlyProperty& p) {
        const std::string& type = p.type;  // a list's item type
        if (plyTypeIsFloat(type)) {
          const FloatToken kind = classifyFloat(token);
          if (kind == FloatToken::NotNumber) {
            throw InputError(where() + ": value '" + lineExcerpt(token) +
                             "' is not a number (property " + p.name + " is " + type + ")");
          }
          if (kind == FloatToken::NonFinite) {
            throw InputError(where() + " has a non-finite value '" + lineExcerpt(token) +
                             "' (NaN, Inf or beyond single precision)");
          }
          return;
        }
        const auto [lo, hi] = plyIntegerRange(type);
        const IntegerToken kind = classifyInteger(token, lo, hi);
        if (kind != IntegerToken::Integer) {
          throw InputError(where() + ": value '" + lineExcerpt(token) + "' is " +
                           (kind == IntegerToken::NotInteger ? "not an integer" : "out of range") +
                           " (property " + p.name + " is " + type + ")");
        }
      };
      for (const PlyProperty& p : e.properties) {
        next();
        if (!p.list) {
          checkValue(p);
          continue;
        }
        const auto [lo, hi] = plyIntegerRange(p.countType);
        if (classifyInteger(token, std::max(lo, 0LL), std::min(hi, kMaxCorners)) !=
            IntegerToken::Integer) {
          throw InputError(where() + " has a list count '" + lineExcerpt(token) +
                           "' (corrupt count?)");
        }
        for (long long k = std::stoll(std::string(token)); k > 0; --k) {
          next();
          checkValue(p);
        }
      }
      // One record per line, as the format writes it: a record that ends mid-line means the
      // header and the body disagree on the properties.
      if (tokens.moreOnLine()) {
        tokens.next(token);
        throw InputError(where() + " ends before the line does (extra value '" +
                         lineExcerpt(token) + "')");
      }
    }
  }
  if (tokens.next(token)) {
    throw InputError(path + ": line " + std::to_string(tokens.lineNo()) + ": extra value '" +
                     lineExcerpt(token) + "' after the last element");
  }
}

void checkPlyBody(const std::string& path, std::ifstream& in, std::size_t headerLines, bool binary,
                  bool bigEndian, const std::vector<PlyElement>& elements) {
  if (binary) {
    checkBinaryPlyBody(path, in, bigEndian, elements);
  } else {
    checkAsciiPlyBody(path, in, headerLines, elements);
  }
}

}  // namespace

bool preflightPly(const std::string& path, std::uint64_t fileBytes) {
  // OpenMesh's PLY reader trusts its header (malformed ones crash it or send it looping), so
  // the header is checked here in full: known keywords only, a known format, typed
  // properties under an element, a vertex element with x, y and z; then the body is walked.
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
  bool bigEndian = false;
  bool formatSeen = false;
  std::vector<PlyElement> elements;
  std::size_t lineNo = 1;
  while (std::getline(in, line)) {
    if (++lineNo > 10000) throw InputError(path + ": PLY header has no end_header");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    for (const char ch : line) {
      const auto c = static_cast<unsigned char>(ch);
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
      bigEndian = kind == "binary_big_endian";
      formatSeen = true;
    } else if (keyword == "element") {
      PlyElement e;
      std::string extra;
      words >> e.name >> e.count;
      if (!words || e.count < 0 || (words >> extra))
        throw bad(lineNo, "bad element line '" + line + "'");
      elements.push_back(e);
    } else if (keyword == "property") {
      if (elements.empty()) throw bad(lineNo, "property before any element");
      PlyProperty p;
      std::string type, name, extra;
      words >> type;
      if (type == "list") {
        p.list = true;
        words >> p.countType >> p.type >> name;
        if (plyTypeBytes(p.countType) < 0 || plyTypeBytes(p.type) < 0 || name.empty() ||
            (words >> extra) || p.countType == "float" || p.countType == "float32" ||
            p.countType == "double" || p.countType == "float64") {
          throw bad(lineNo, "bad list property '" + line + "'");
        }
      } else {
        p.type = type;
        words >> name;
        if (plyTypeBytes(type) < 0 || name.empty() || (words >> extra)) {
          throw bad(lineNo, "bad property '" + line + "'");
        }
      }
      p.name = name;
      p.coordinate = elements.back().name == "vertex" && !p.list &&
                     (name == "x" || name == "y" || name == "z");
      elements.back().properties.push_back(p);
    } else if (keyword == "end_header") {
      if (!formatSeen) throw InputError(path + ": PLY header has no format line");
      int xyz = 0;
      long double needBytes = 0.0L;
      for (const PlyElement& e : elements) {
        if (e.properties.empty() && e.count > 0) {
          throw InputError(path + ": PLY element '" + e.name + "' has records but no properties");
        }
        long double record = 0.0L;
        for (const PlyProperty& p : e.properties) {
          record += binary ? (p.list ? plyTypeBytes(p.countType) : plyTypeBytes(p.type)) : 2;
          if (p.coordinate) ++xyz;
        }
        needBytes += record * static_cast<long double>(e.count);
      }
      if (xyz != 3) throw InputError(path + ": PLY header has no vertex element with x, y and z");
      const auto headerEnd = static_cast<std::uint64_t>(in.tellg());
      if (needBytes > static_cast<long double>(fileBytes - headerEnd)) {
        throw InputError(path + ": PLY header promises more elements than its " +
                         std::to_string(fileBytes) + " bytes can hold (truncated file?)");
      }
      checkPlyBody(path, in, lineNo, binary, bigEndian, elements);
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
        throw InputError(path + ": triangle " + std::to_string(tri) +
                         " has a non-finite vertex coordinate (" + std::to_string(coords[k]) + ")");
      }
    }
  }
}

}  // namespace osteon::geometry::detail
