// Where a NRRD header's data lies and reading it (nrrd_header.h): the data file's name checked
// against the header's folder, line and byte skips, raw and gzip lengths against the sizes.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <zlib.h>

#include "io/huge_pages.h"
#include "io/nrrd_header.h"
#include "osteon/core/error.h"
#include "osteon/core/input_file.h"

namespace osteon::geometry::nrrd {

namespace fs = std::filesystem;

namespace {

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
                       " (it resolves to " + realFile.string() + "); give " +
                       optionRef("volume.allowOutsideData") + " to read it");
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
  std::vector<unsigned char> out;
  out.reserve(expected);
  adviseHugePages(out.data(), expected);
  out.resize(expected);
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
