#include "io/nrrd_header.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <zlib.h>

#include "osteon/core/error.h"
#include "osteon/core/input_file.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry::nrrd {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxHeaderLine = 65536;

std::vector<std::string> words(const std::string& s) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while ((pos = s.find_first_not_of(" \t\r", pos)) != std::string::npos) {
    const std::size_t end = std::min(s.find_first_of(" \t\r", pos), s.size());
    out.push_back(s.substr(pos, end - pos));
    pos = end;
  }
  return out;
}

bool parseInteger(const std::string& text, long long& v) {
  const std::string t = trim(text);
  const char* first = t.data();
  const char* last = first + t.size();
  if (first != last && *first == '+') ++first;
  const auto r = std::from_chars(first, last, v);
  return first != last && r.ec == std::errc() && r.ptr == last;
}

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
  for (unsigned char c : text) {
    if (!std::isspace(c) && c != '_') name += static_cast<char>(std::tolower(c));
  }
  return name;
}

// True when `inner` lies inside the folder `folder` (both absolute and canonical).
bool isInside(const fs::path& inner, const fs::path& folder) {
  auto f = folder.begin();
  auto i = inner.begin();
  for (; f != folder.end(); ++f, ++i) {
    if (f->empty()) continue;  // a trailing separator
    if (i == inner.end() || *i != *f) return false;
  }
  return true;  // the folder itself is inside (and then refused as not a regular file)
}

void failAt(const std::string& shown, const std::string& reason) {
  throw InputError(shown + ": " + reason);
}

// Every loader's check of a name (core/input_file.h), with the name as this reader shows it.
void checkRegularFile(const std::string& path, const std::string& shown) {
  const std::string problem = inputFileProblem(path);
  if (!problem.empty()) failAt(printableFileName(shown), problem);
}

// A `data file:` value that names several files: "LIST" (names follow the header) or a
// numbered pattern "<format> <min> <max> <step> [<subdim>]". Anything else is one file name,
// blanks included.
void refuseSeveralDataFiles(const Header& h, const std::string& value) {
  const std::vector<std::string> w = words(value);
  if (!w.empty() && w[0] == "LIST") {
    h.fail("data file " + excerpt(value) +
           ": a list of data files (LIST) is not supported; only a single data file is");
  }
  if (w.size() >= 4 && w.size() <= 5 && w[0].find('%') != std::string::npos) {
    long long n;
    bool numbers = true;
    for (std::size_t i = 1; i < w.size(); ++i) numbers = numbers && parseInteger(w[i], n);
    if (numbers) {
      h.fail(
          "data file " + excerpt(value) +
          ": numbered data files (a '%' pattern with min, max and step) are not supported; only a "
          "single data file is");
    }
  }
}

// Resolves `data file:` against the header's folder; refuses it outside that folder.
std::string dataFilePath(const Header& h, const std::string& name, bool allowOutsideData) {
  if (name.empty()) h.fail("'data file' names no file");
  // The system reads a name only up to a NUL: what follows it would be checked but not opened.
  if (name.find('\0') != std::string::npos) {
    h.fail("data file '" + printableFileName(name) + "': the file name contains a NUL byte");
  }
  if (std::any_of(name.begin(), name.end(),
                  [](unsigned char c) { return c < 0x20 || c == 0x7f; })) {
    h.fail("data file " + excerpt(name) +
           ": the name holds a control character (a NUL or the like)");
  }
  fs::path folder = fs::path(h.path).parent_path();
  if (folder.empty()) folder = ".";
  const fs::path named(name);
  const fs::path file = named.is_absolute() ? named : folder / named;
  const std::string shown = h.path + ": data file " + file.string();
  if (!allowOutsideData) {
    // `..` and symlinks resolved: a name inside the folder may still lead out of it.
    std::error_code ec1, ec2;
    const fs::path realFolder = fs::weakly_canonical(fs::absolute(folder), ec1);
    const fs::path realFile = fs::weakly_canonical(fs::absolute(file), ec2);
    if (ec1 || ec2) failAt(shown, "cannot resolve the name (" + (ec1 ? ec1 : ec2).message() + ")");
    if (!isInside(realFile, realFolder)) {
      throw InputError(shown + " is outside the header's folder " + realFolder.string() +
                       " (it resolves to " + realFile.string() +
                       "); give --allow-outside-data to read it");
    }
  }
  checkRegularFile(file.string(), shown);
  return file.string();
}

// Offset after `lines` more newlines from `offset`, read in small pieces.
std::uint64_t skipLines(const DataLocation& at, std::uint64_t offset, long long lines) {
  std::ifstream in(at.path, std::ios::binary);
  if (!in) failAt(at.shown, "cannot open (" + std::string(std::strerror(errno)) + ")");
  in.seekg(std::streamoff(offset));
  std::vector<char> chunk(1 << 16);
  const std::uint64_t from = offset;
  long long found = 0;
  while (found < lines) {
    in.read(chunk.data(), std::streamsize(chunk.size()));
    const std::size_t n = std::size_t(in.gcount());
    if (n == 0) {
      failAt(at.shown, "line skip " + std::to_string(lines) + " runs past the end of the file (" +
                           std::to_string(found) + (found == 1 ? " line" : " lines") + " after " +
                           (from == 0 ? std::string("its start") : "the header") + ")");
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (chunk[i] == '\n' && ++found == lines) return offset + i + 1;
    }
    offset += n;
  }
  return offset;
}

}  // namespace

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
    if (!(sizes[a] >= 1 && sizes[a] <= double(1 << 30) && sizes[a] == std::floor(sizes[a]))) {
      h.fail("sizes " + excerpt(sizesText) + " are not three integers from 1 to 2^30");
    }
    n[a] = int(sizes[a]);
    voxels *= std::uint64_t(n[a]);
    if (voxels > VoxelGrid::kMaxVoxels)
      h.fail("sizes " + excerpt(sizesText) + " exceed 2^32 voxels");
  }
  // A colour or vector axis holds components of one sample, not positions in space.
  if (const std::string* kinds = h.field("kinds")) {
    const std::vector<std::string> k = words(*kinds);
    if (k.size() != 3) h.fail("kinds " + excerpt(*kinds) + " are not three (one per axis)");
    for (int a = 0; a < 3; ++a) {
      const std::string kind = normaliseWords(k[a]);
      if (kind != "domain" && kind != "space" && kind != "???" && kind != "none") {
        h.fail("kinds " + excerpt(*kinds) + ": axis " + std::to_string(a) + " is " + excerpt(k[a]) +
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

DataLocation locateData(const Header& h, std::uint64_t expectedBytes, bool gzip,
                        bool allowOutsideData) {
  DataLocation at;
  std::uint64_t start = 0;
  if (const std::string* dataFile = h.field("datafile")) {
    const std::string name = trim(*dataFile);
    refuseSeveralDataFiles(h, name);
    at.path = dataFilePath(h, name, allowOutsideData);
    at.shown = h.path + ": data file " + at.path;
  } else {
    at.path = h.path;
    at.shown = h.path;
    start = h.headerBytes;
  }
  std::error_code ec;
  const std::uint64_t fileBytes = fs::file_size(at.path, ec);
  if (ec) failAt(at.shown, "cannot read its size (" + ec.message() + ")");
  if (start > fileBytes) failAt(at.shown, "truncated: no data after the header");

  long long lineSkip = 0, byteSkip = 0;
  if (const std::string* v = h.field("lineskip");
      v && (!parseInteger(*v, lineSkip) || lineSkip < 0)) {
    h.fail("line skip " + excerpt(*v) + " is not a whole number of lines (0 or more)");
  }
  if (const std::string* v = h.field("byteskip");
      v && (!parseInteger(*v, byteSkip) || byteSkip < -1)) {
    h.fail("byte skip " + excerpt(*v) +
           " is not a whole number of bytes (0 or more, or -1 for the file's end)");
  }
  at.offset = lineSkip > 0 ? skipLines(at, start, lineSkip) : start;
  const std::string skipped = lineSkip > 0 || byteSkip != 0 ? " after the line and byte skips" : "";

  if (gzip) {
    // Inflated data can only be measured by inflating it; its skip applies there.
    if (byteSkip == -1) {
      h.fail(
          "byte skip -1 (data at the end of the file) is only for raw encoding; gzip data cannot "
          "be found "
          "from the file's end");
    }
    at.inflatedSkip = std::uint64_t(byteSkip);
    at.bytes = fileBytes - at.offset;
    if (expectedBytes + at.inflatedSkip > at.bytes * kMaxDeflateRatio + 1024) {
      failAt(at.shown, "truncated: " + std::to_string(at.bytes) + " bytes of gzip data" + skipped +
                           " cannot hold the " + std::to_string(expectedBytes + at.inflatedSkip) +
                           " bytes the sizes" + (at.inflatedSkip ? " and the byte skip" : "") +
                           " need");
    }
    return at;
  }
  if (byteSkip == -1) {
    // The data is the file's last bytes; whatever precedes it is skipped.
    if (fileBytes - at.offset < expectedBytes) {
      failAt(at.shown, "truncated: " + std::to_string(fileBytes - at.offset) + " bytes of data" +
                           skipped + ", sizes need " + std::to_string(expectedBytes));
    }
    at.offset = fileBytes - expectedBytes;
  } else if (std::uint64_t(byteSkip) > fileBytes - at.offset) {
    failAt(at.shown, "truncated: byte skip " + std::to_string(byteSkip) +
                         " passes the end of the file (" + std::to_string(fileBytes - at.offset) +
                         " bytes after the " +
                         (lineSkip > 0        ? "line skip"
                          : at.path == h.path ? "header"
                                              : "file's start") +
                         ")");
  } else {
    at.offset += std::uint64_t(byteSkip);
  }
  // The whole length is known before a byte is read: a lie is refused at once.
  at.bytes = fileBytes - at.offset;
  if (at.bytes < expectedBytes) {
    failAt(at.shown, "truncated: " + std::to_string(at.bytes) + " bytes of data" + skipped +
                         ", sizes need " + std::to_string(expectedBytes));
  }
  if (at.bytes > expectedBytes) {
    failAt(at.shown, std::to_string(at.bytes) + " bytes of data" + skipped +
                         " disagree with sizes, which need " + std::to_string(expectedBytes));
  }
  return at;
}

std::ifstream openData(const DataLocation& at) {
  std::ifstream in(at.path, std::ios::binary);
  if (!in) failAt(at.shown, "cannot open (" + std::string(std::strerror(errno)) + ")");
  in.seekg(std::streamoff(at.offset));
  if (!in) failAt(at.shown, "cannot seek to its data");
  return in;
}

std::vector<unsigned char> inflateData(const DataLocation& at, std::uint64_t expected) {
  std::ifstream in = openData(at);
  struct Stream {
    z_stream z{};
    ~Stream() { inflateEnd(&z); }
  } s;
  z_stream& z = s.z;
  if (inflateInit2(&z, 15 + 32) != Z_OK) failAt(at.shown, "zlib failed to start");
  std::vector<unsigned char> out(expected);
  std::vector<unsigned char> chunk(1 << 16);
  std::vector<unsigned char> skipped(
      std::size_t(std::min<std::uint64_t>(at.inflatedSkip, 1 << 16)));
  std::uint64_t unread = at.bytes;  // compressed bytes not yet read
  std::uint64_t skipLeft = at.inflatedSkip;
  std::uint64_t produced = 0;
  unsigned char extra = 0;
  // Keeps at least `want` compressed bytes at z.next_in when the file has them.
  const auto refill = [&](std::size_t want) {
    if (z.avail_in >= want || unread == 0) return;
    std::memmove(chunk.data(), z.next_in, z.avail_in);
    const std::size_t n = std::size_t(std::min<std::uint64_t>(chunk.size() - z.avail_in, unread));
    in.read(reinterpret_cast<char*>(chunk.data() + z.avail_in), std::streamsize(n));
    if (std::size_t(in.gcount()) != n) failAt(at.shown, "read failed in the gzip data");
    unread -= n;
    z.next_in = chunk.data();
    z.avail_in += uInt(n);
  };
  z.next_in = chunk.data();
  int rc = Z_OK;
  for (;;) {
    refill(1);
    unsigned char* const before = skipLeft > 0          ? skipped.data()
                                  : produced < expected ? out.data() + produced
                                                        : &extra;
    const uInt room =
        uInt(skipLeft > 0          ? std::min<std::uint64_t>(skipLeft, skipped.size())
             : produced < expected ? std::min<std::uint64_t>(expected - produced, 1u << 30)
                                   : 1);
    z.next_out = before;
    z.avail_out = room;
    rc = inflate(&z, Z_NO_FLUSH);
    const uInt wrote = room - z.avail_out;
    if (skipLeft > 0) {
      skipLeft -= wrote;
    } else if (produced < expected) {
      produced += wrote;
    } else if (wrote > 0) {
      // Bounded: inflating stops at the first byte past what the sizes need.
      failAt(
          at.shown,
          "gzip data is longer than the sizes need (" + std::to_string(expected) + " bytes" +
              (at.inflatedSkip ? " after a byte skip of " + std::to_string(at.inflatedSkip) : "") +
              ")");
    }
    if (rc == Z_STREAM_END) {
      // Another gzip member may follow (as `cat a.gz b.gz` makes); anything else after the
      // stream is data the sizes do not account for, refused as raw data that is too long is.
      refill(2);
      if (z.avail_in >= 2 && z.next_in[0] == 0x1f && z.next_in[1] == 0x8b) {
        inflateReset(&z);
        continue;
      }
      if (z.avail_in + unread > 0 && produced == expected && skipLeft == 0) {
        failAt(at.shown, std::to_string(z.avail_in + unread) +
                             " bytes follow the end of the gzip data (" + "it holds the " +
                             std::to_string(expected) + " bytes the sizes need)");
      }
      break;
    }
    if (rc == Z_BUF_ERROR && z.avail_in == 0 && unread == 0) break;  // the file ends mid-stream
    if (rc != Z_OK && rc != Z_BUF_ERROR) {
      failAt(at.shown,
             std::string("gzip data is corrupt (") + (z.msg ? z.msg : "zlib error") + ")");
    }
  }
  if (produced < expected || skipLeft > 0) {
    failAt(at.shown, "truncated: " + std::to_string(produced) + " bytes of gzip data, sizes need " +
                         std::to_string(expected));
  }
  if (rc != Z_STREAM_END) failAt(at.shown, "truncated: the gzip stream ends before its checksum");
  return out;
}

}  // namespace osteon::geometry::nrrd
