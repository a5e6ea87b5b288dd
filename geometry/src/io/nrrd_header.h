// One reader of NRRD headers for both of osteon's NRRD loaders (its own grids, nrrd_io.cpp,
// and users' volumes, volume_io.cpp): the header's fields and keys, the axes, the scalar layout
// and where the data lies. Geometry (space, directions, origin) stays with each loader, which
// read it differently (osteon's grids are LPS only and carry exact keys).
// Every refusal is an InputError "<header>: <reason>" (or "<header>: data file <file>: ...").
#pragma once

#include <cstdint>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "osteon/core/number_text.h"

namespace osteon::geometry::nrrd {

// deflate never compresses more than about 1032:1: more than that is a lie, refused unallocated.
inline constexpr std::uint64_t kMaxDeflateRatio = 1032;

struct Header {
  std::string path;                           // the header file, as named
  std::map<std::string, std::string> fields;  // "sizes" -> "3 2 2": names lowercase, no blanks
  std::map<std::string, std::string> keys;    // "key:=value" lines, as written
  std::vector<std::string> comments;          // "# ..." lines, without the '#'
  std::uint64_t headerBytes = 0;              // offset of the first byte after the blank line
  bool ended = false;                         // a blank line ends the header (else end of file)

  const std::string* field(const char* name) const;
  const std::string& require(const char* name, const char* shown) const;
  [[noreturn]] void fail(const std::string& reason) const;
};

// Text helpers every NRRD reader shares (nrrd_text.cpp): blanks trimmed; lowercase with runs of
// blanks made one space ("Unsigned  Char" -> "unsigned char"); file text as one short printable
// quoted excerpt.
std::string trim(const std::string& s);
std::string normaliseWords(const std::string& s);
std::string excerpt(const std::string& s);

// The one number parser of every NRRD field: a finite decimal in the C locale (a leading '+'
// allowed, nothing after it), as std::from_chars reads it.
bool parseNumber(const std::string& token, double& v);
// Whitespace- and/or comma-separated numbers, parentheses dropped: "(1, 2,3)" -> 1 2 3. False
// when any token is not a number.
bool parseNumbers(std::string text, std::vector<double>& values);
// Blank-separated words; a whole number (a leading '+' allowed, blanks around it trimmed).
std::vector<std::string> words(const std::string& s);
bool parseInteger(const std::string& text, long long& v);

// "<shown>: <reason>" as an InputError; every loader's check that a name is a regular file
// (core/input_file.h), with the name as this reader shows it.
[[noreturn]] void failAt(const std::string& shown, const std::string& reason);
void checkRegularFile(const std::string& path, const std::string& shown);

// Reads the header of `path` (nrrd_header.cpp): the magic (NRRD0001..NRRD0005), field and key lines
// up to the blank line. Refuses a file that is missing or not regular, a line longer than 64 KiB, a
// malformed line, a field or key given twice, and an attached header with no blank line.
Header readHeader(const std::string& path);

// Which of osteon's own files this is, by everything `osteon voxelize --out` writes: the
// content line and both osteon_voxel_size_mm and osteon_origin_mm. One stray osteon_* key or
// the comment alone does not make a user's volume an osteon file.
enum class OsteonFile { None, Fill, Density };
OsteonFile osteonFile(const Header& h);

// dimension 3, three sizes from 1 to 2^30 with at most 2^32 voxels, and kinds (when given)
// that are spatial: domain, space or unknown ("???", "none"). A colour, vector or list axis is
// not a spatial axis and is refused.
glm::ivec3 readSizes(const Header& h);

struct Scalar {
  std::string name;       // "uint8", "int16", "float", ...
  std::size_t bytes = 0;  // per value
  bool integer = true;
  bool isSigned = false;
};
std::optional<Scalar> scalarNamed(const std::string& typeText);

// type, encoding (raw or gzip) and endian (required for multi-byte values).
struct Layout {
  Scalar scalar;
  bool gzip = false;
  bool bigEndian = false;
};
Layout readLayout(const Header& h);

// Where the data lies (nrrd_data.cpp): the header's own file after its blank line, or its `data
// file:`, then `line skip:` lines and `byte skip:` bytes on (byte skip -1: the last bytes of a raw
// file; for gzip the byte skip is of the inflated stream). Checked before any data is read: a data
// file outside the header's folder (after `..` and symlinks) unless allowOutsideData, a list
// or numbered data files, a raw data length other than `expectedBytes`, gzip data too short
// to inflate to it.
struct DataLocation {
  std::string path;                // the file that holds the data
  std::string shown;               // how messages name it ("H" or "H: data file D")
  std::uint64_t offset = 0;        // first data byte (gzip: of the compressed stream)
  std::uint64_t bytes = 0;         // from offset to the file's end
  std::uint64_t inflatedSkip = 0;  // gzip: bytes of the inflated stream before the data
};
DataLocation locateData(const Header& h, std::uint64_t expectedBytes, bool gzip,
                        bool allowOutsideData);

// The data file opened at its first data byte.
std::ifstream openData(const DataLocation& at);

// Inflates gzip data into exactly `expected` bytes, reading the file in small pieces: data that
// inflates to more is refused as soon as the first byte too many appears.
std::vector<unsigned char> inflateData(const DataLocation& at, std::uint64_t expected);

}  // namespace osteon::geometry::nrrd
