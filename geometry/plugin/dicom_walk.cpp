// Every element length in a DICOM file checked against the file before GDCM reads it: GDCM
// allocates what a header declares (a 4 GB element in a 1 KB file) before it finds the file
// too short. Only the element headers are read; values are skipped.
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "dicom_series.h"

namespace osteon::dicom {

namespace {

constexpr std::uint32_t kUndefined = 0xffffffff;

struct Walker {
  std::ifstream in;
  std::string name;
  bool explicitVr = true;

  std::uint32_t read(std::uint64_t at, int bytes) {
    unsigned char b[4] = {0, 0, 0, 0};
    in.clear();
    in.seekg(std::streamoff(at));
    in.read(reinterpret_cast<char*>(b), bytes);
    if (in.gcount() != bytes) fail(name + ": truncated: an element header runs past the file");
    std::uint32_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = v << 8 | b[i];
    return v;
  }

  static bool longVr(const std::string& vr) {
    static const std::string kLong = "OB OD OF OL OV OW SQ UC UN UR UT SV UV";
    return kLong.find(vr) != std::string::npos;
  }

  // Walks elements from `at` to `end` (or, `end` undefined, to a delimiter); returns where it
  // stopped (after the delimiter). In encapsulated pixel data (`fragments`) items hold bytes,
  // not elements.
  std::uint64_t walk(std::uint64_t at, std::uint64_t end, std::uint64_t fileEnd, int depth,
                     bool fragments = false) {
    if (depth > 32) fail(name + ": sequences nested more than 32 deep");
    while (at < end && at + 8 <= fileEnd) {
      const std::uint32_t group = read(at, 2), element = read(at + 2, 2);
      std::uint64_t length = 0;
      bool sequence = false;
      if (group == 0xfffe) {  // item, item delimiter, sequence delimiter: no VR
        length = read(at + 4, 4);
        at += 8;
        if (element == 0xe00d || element == 0xe0dd) return at;
        sequence = !fragments;
      } else if (explicitVr) {
        char vr[2];
        vr[0] = char(read(at + 4, 1));
        vr[1] = char(read(at + 5, 1));
        const std::string v(vr, 2);
        // GDCM falls back to implicit VR where the bytes are no VR, and then trusts lengths
        // this walk did not see: a data set must be what its transfer syntax says.
        if (!isVr(v)) {
          fail(name + ": element (" + hex(group) + "," + hex(element) +
               ") has no valid VR, though its transfer syntax says explicit VR");
        }
        if (longVr(v)) {
          length = read(at + 8, 4);
          at += 12;
        } else {
          length = read(at + 6, 2);
          at += 8;
        }
        sequence = v == "SQ";
      } else {
        length = read(at + 4, 4);
        at += 8;
      }
      if (length == kUndefined) {
        // A sequence, an item, or encapsulated pixel data (fragments in items).
        at = walk(at, std::uint64_t(-1), fileEnd, depth + 1, group == 0x7fe0 && element == 0x0010);
        continue;
      }
      if (length > fileEnd - at) {
        fail(name + ": truncated: element (" + hex(group) + "," + hex(element) + ") declares " +
             std::to_string(length) + " bytes, the file holds " + std::to_string(fileEnd - at) +
             " after it");
      }
      if (sequence) walk(at, at + length, at + length, depth + 1);
      at += length;
    }
    return at;
  }

  static std::string hex(std::uint32_t v) {
    static const char* digits = "0123456789abcdef";
    std::string s(4, '0');
    for (int i = 3; i >= 0; --i, v >>= 4) s[std::size_t(i)] = digits[v & 15];
    return s;
  }
};

}  // namespace

bool isVr(const std::string& vr) {
  static const std::string kVrs =
      "AE AS AT CS DA DS DT FD FL IS LO LT OB OD OF OL OV OW PN SH SL SQ SS ST SV TM UC UI UL UN "
      "UR US UT UV";
  return vr.size() == 2 && std::isupper(static_cast<unsigned char>(vr[0])) &&
         std::isupper(static_cast<unsigned char>(vr[1])) && kVrs.find(vr) != std::string::npos;
}

void refuseLyingLengths(const std::string& file, const std::string& transferSyntax) {
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(file, ec);
  // Big-endian data (retired) and files without the DICM preamble are left to GDCM.
  if (ec || size < 132 || transferSyntax == "1.2.840.10008.1.2.2") return;
  Walker w{std::ifstream(file, std::ios::binary), std::filesystem::path(file).filename().string(),
           transferSyntax != "1.2.840.10008.1.2"};
  if (!w.in) return;
  char magic[4] = {0, 0, 0, 0};
  w.in.seekg(128);
  w.in.read(magic, 4);
  if (std::string(magic, 4) != "DICM") return;
  // The file meta group is always explicit VR little endian.
  const bool dataSetExplicit = w.explicitVr;
  w.explicitVr = true;
  std::uint64_t at = 132;
  while (at + 8 <= size && w.read(at, 2) == 0x0002) at = w.walk(at, at + 1, size, 0);
  w.explicitVr = dataSetExplicit;
  w.walk(at, size, size, 0);
}

}  // namespace osteon::dicom
