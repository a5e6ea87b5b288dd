// Checks that run before any parser touches a file: what kind of STL it is, and whether the
// counts in a header can possibly fit in the file (so no reader loops over 2^31 phantom
// records or allocates for them).
#pragma once

#include <cstdint>
#include <string>

namespace osteon::geometry::detail {

enum class StlKind { Binary, Ascii };

// Decides binary vs ASCII by the binary size law (84 + 50 n bytes), not by the "solid"
// prefix that many CAD exporters also write into binary headers. Throws InputError for a
// truncated or padded binary file and for a count whose byte size overflows 32 bits.
StlKind preflightStl(const std::string& path, std::uint64_t fileBytes);

// Rejects a binary STL with a NaN or Inf vertex coordinate (OpenMesh's vertex merging
// would otherwise drop such triangles without a word).
void checkBinaryStlFinite(const std::string& path);

// OBJ and ASCII STL ("obj" or "stl"): rejects NaN, Inf and beyond-float coordinates (text
// parsers stop at "nan" and go on with the next record, silently losing a vertex) and OBJ
// faces without three usable corners (OpenMesh's reader asserts on them).
void checkObjOrAsciiStl(const std::string& path, const std::string& format);

// Rejects OFF and PLY files whose headers or records the parsers would trust to a crash, a
// loop or a huge allocation: counts that cannot fit in fileBytes, corner counts the record
// does not hold, non-finite coordinates, binary OFF (unsupported). Return whether the body
// is binary.
bool preflightOff(const std::string& path, std::uint64_t fileBytes);
bool preflightPly(const std::string& path, std::uint64_t fileBytes);

}  // namespace osteon::geometry::detail
