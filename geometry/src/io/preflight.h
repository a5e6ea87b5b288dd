// Checks that run before any parser touches a file: what kind of STL it is, and whether the
// counts in a header can possibly fit in the file (so no reader loops over 2^31 phantom
// records or allocates for them).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace osteon::geometry::detail {

// Corners of one polygon (OFF, PLY faces); more is a corrupt count.
inline constexpr long long kMaxCorners = 1024;

enum class StlKind { Binary, Ascii };

// Decides binary vs ASCII by the binary size law (84 + 50 n bytes), not by the "solid"
// prefix that many CAD exporters also write into binary headers. Throws InputError for a
// truncated or padded binary file and for a count whose byte size overflows 32 bits.
StlKind preflightStl(const std::string& path, std::uint64_t fileBytes);

// Rejects a binary STL with a NaN or Inf vertex coordinate (OpenMesh's vertex merging
// would otherwise drop such triangles without a word).
void checkBinaryStlFinite(const std::string& path);

// True for a head (the file's first bytes) that reads as ASCII STL with a flaw: its keywords
// and hardly a control byte once trailing NUL padding is set aside.
bool looksLikeAsciiStl(const std::string& head);

// ASCII STL, strictly: solid / facet normal nx ny nz / outer loop / three vertex x y z lines /
// endloop / endfacet / endsolid, coordinates finite within single precision (OpenMesh's reader
// would silently read a bad token as 0 or take any three lines as corners). NUL padding after
// the last line is accepted. Errors name the line.
void checkAsciiStl(const std::string& path);

// OBJ: v lines with three finite numbers (a trailing w or colour is allowed), f lines with
// three usable corners (OpenMesh's reader asserts on fewer). Errors name the line.
void checkObj(const std::string& path);

// A vertex record's coordinates tokens[first .. first + 2]: each a finite number within single
// precision; exactlyThree forbids further tokens.
void checkVertexLine(const std::string& path, std::size_t lineNo,
                     const std::vector<std::string_view>& tokens, std::size_t first,
                     bool exactlyThree);

// Rejects OFF and PLY files whose headers or records the parsers would trust to a crash, a
// loop or a huge allocation: counts that cannot fit in fileBytes, corner counts the record
// does not hold, vertex lines without three finite numbers, ASCII PLY values that are not
// numbers of their declared type, binary OFF (unsupported). Return whether the body is binary.
bool preflightOff(const std::string& path, std::uint64_t fileBytes);
bool preflightPly(const std::string& path, std::uint64_t fileBytes);

}  // namespace osteon::geometry::detail
