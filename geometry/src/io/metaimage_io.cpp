// MetaImage (ITK's .mha and .mhd): "Key = Value" lines up to ElementDataFile, which is last and
// says where the data is (LOCAL: right after that line). ITK's physical space is LPS, with
// Offset the centre of voxel (0,0,0) and TransformMatrix's rows the directions of the axes.
// Where the data lies and how it inflates is the NRRD reader's code (nrrd_data.cpp), fed a
// header that says the same: one check of data files outside the folder, lists and patterns.
#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>

#include "io/nrrd_header.h"
#include "io/volume_place.h"
#include "io/volume_readers.h"
#include "osteon/core/error.h"
#include "osteon/core/input_file.h"

namespace osteon::geometry::io {

namespace {

using nrrd::excerpt;
using nrrd::trim;

std::string lowerText(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

struct MetaHeader {
  std::string path;
  std::map<std::string, std::string> fields;  // lowercase key -> value as written
  std::map<std::string, std::string> named;   // lowercase key -> the key as written
  std::uint64_t headerBytes = 0;              // first byte after the ElementDataFile line
  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(path + ": " + reason);
  }
  // The key as written of the first of `names` given.
  std::string shown(std::initializer_list<const char*> names) const {
    for (const char* name : names) {
      if (named.count(name)) return named.at(name);
    }
    return *names.begin();
  }
  // The value of the first key given among `names` (synonyms); two of them given is refused.
  const std::string* field(std::initializer_list<const char*> names) const {
    const std::string* found = nullptr;
    std::string first;
    for (const char* name : names) {
      const auto it = fields.find(name);
      if (it == fields.end()) continue;
      if (found) fail(first + " and " + named.at(name) + " both given (they say the same)");
      found = &it->second;
      first = named.at(name);
    }
    return found;
  }
};

// Reads the header lines up to ElementDataFile (64 KiB lines, 1 MiB in all at most).
MetaHeader readMetaHeader(const std::string& path) {
  requireInputFile(path);
  std::ifstream in(path, std::ios::binary);
  MetaHeader h;
  h.path = path;
  if (!in) h.fail("cannot open");
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    h.headerBytes += line.size() + 1;
    if (h.headerBytes > (1u << 20)) h.fail("no ElementDataFile line in its first 1 MiB");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty()) continue;
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) {
      h.fail("line " + std::to_string(lineNo) + " " + excerpt(line) +
             " is not 'Key = Value' (not a MetaImage header?)");
    }
    const std::string key = trim(line.substr(0, eq));
    const std::string lowerKey = lowerText(key);
    if (h.fields.count(lowerKey)) h.fail(key + " given twice");
    h.fields[lowerKey] = trim(line.substr(eq + 1));
    h.named[lowerKey] = key;
    if (lowerKey == "elementdatafile") return h;
  }
  if (h.fields.empty()) h.fail("not a MetaImage file (no 'Key = Value' lines)");
  h.fail("no ElementDataFile line (where the data is)");
}

std::vector<double> numbers(const MetaHeader& h, std::initializer_list<const char*> names,
                            std::size_t count, const std::vector<double>& otherwise) {
  const std::string* text = h.field(names);
  if (!text) return otherwise;
  std::vector<double> v;
  if (!nrrd::parseNumbers(*text, v) || v.size() != count) {
    h.fail(h.shown(names) + " " + excerpt(*text) + " is not " + std::to_string(count) + " numbers");
  }
  return v;
}

bool flag(const MetaHeader& h, std::initializer_list<const char*> names) {
  const std::string* text = h.field(names);
  if (!text) return false;
  const std::string v = lowerText(*text);
  if (v == "true" || v == "1") return true;
  if (v == "false" || v == "0") return false;
  h.fail(h.shown(names) + " " + excerpt(*text) + " is not True or False");
}

nrrd::Scalar elementType(const MetaHeader& h) {
  static const std::map<std::string, nrrd::Scalar> kTypes = {
      {"MET_CHAR", {"int8", 1, true, true}},       {"MET_UCHAR", {"uint8", 1, true, false}},
      {"MET_SHORT", {"int16", 2, true, true}},     {"MET_USHORT", {"uint16", 2, true, false}},
      {"MET_INT", {"int32", 4, true, true}},       {"MET_UINT", {"uint32", 4, true, false}},
      {"MET_LONG", {"int32", 4, true, true}},      {"MET_ULONG", {"uint32", 4, true, false}},
      {"MET_LONG_LONG", {"int64", 8, true, true}}, {"MET_ULONG_LONG", {"uint64", 8, true, false}},
      {"MET_FLOAT", {"float", 4, false, true}},    {"MET_DOUBLE", {"double", 8, false, true}}};
  const std::string* text = h.field({"elementtype"});
  if (!text) h.fail("no ElementType");
  const auto it = kTypes.find(*text);
  if (it == kTypes.end()) h.fail("ElementType " + excerpt(*text) + " is not a MET_ scalar type");
  return it->second;
}

// AnatomicalOrientation as ITK writes it: each letter the side an axis comes from ("RAI": x
// from right to left, y from anterior to posterior, z from inferior to superior, LPS itself).
bool orientationDirections(const MetaHeader& h, double dir[3][3]) {
  const std::string* text = h.field({"anatomicalorientation"});
  if (!text || text->find('?') != std::string::npos) return false;
  std::string code = *text;
  std::transform(code.begin(), code.end(), code.begin(),
                 [](unsigned char c) { return char(std::toupper(c)); });
  static const std::string kFrom = "RAILPS";
  bool used[3] = {false, false, false};
  if (code.size() != 3) h.fail("AnatomicalOrientation " + excerpt(*text) + " is not 3 letters");
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t at = kFrom.find(code[std::size_t(axis)]);
    if (at == std::string::npos || used[at % 3]) {
      h.fail("AnatomicalOrientation " + excerpt(*text) +
             " is not one of R/L, A/P, I/S for each axis");
    }
    used[at % 3] = true;
    for (int r = 0; r < 3; ++r) dir[axis][r] = 0.0;
    dir[axis][at % 3] = at < 3 ? 1.0 : -1.0;
  }
  return true;
}

}  // namespace

StoredVolume readMetaImage(const std::string& path, bool allowOutsideData) {
  const MetaHeader h = readMetaHeader(path);
  if (const std::string* type = h.field({"objecttype"}); type && lowerText(*type) != "image")
    h.fail("ObjectType " + excerpt(*type) + " is not an Image");
  const std::vector<double> ndims = numbers(h, {"ndims"}, 1, {});
  if (ndims.empty()) h.fail("no NDims");
  if (ndims[0] != 3) h.fail("NDims " + numberText(ndims[0]) + " is not supported (need 3)");
  if (numbers(h, {"elementnumberofchannels"}, 1, {1})[0] != 1)
    h.fail("ElementNumberOfChannels is not 1 (a vector or colour image, not a scalar volume)");
  if (const std::string* binary = h.field({"binarydata"}); binary && !flag(h, {"binarydata"}))
    h.fail("BinaryData False (values as text) is not supported: save as binary");
  StoredVolume out;
  RawVolume& v = out.volume;
  const std::vector<double> sizes = numbers(h, {"dimsize"}, 3, {});
  if (sizes.empty()) h.fail("no DimSize");
  std::uint64_t voxels = 1;
  for (int a = 0; a < 3; ++a) {
    const double size = sizes[std::size_t(a)];
    if (!(size >= 1 && size <= double(1 << 30) && size == std::floor(size)))
      h.fail("DimSize is not three integers from 1 to 2^30");
    v.sizes[a] = int(size);
    voxels *= std::uint64_t(v.sizes[a]);
    if (voxels > VoxelGrid::kMaxVoxels) h.fail("DimSize exceeds 2^32 voxels");
  }
  const nrrd::Scalar scalar = elementType(h);
  v.integer = scalar.integer;
  v.isSigned = scalar.isSigned;
  const std::vector<double> spacing =
      numbers(h, {"elementspacing", "elementsize"}, 3, {1.0, 1.0, 1.0});
  const std::vector<double> offset = numbers(h, {"offset", "position", "origin"}, 3, {0, 0, 0});
  double dir[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // dir[axis] = its LPS direction
  const std::vector<double> matrix =
      numbers(h, {"transformmatrix", "rotation", "orientation"}, 9, {});
  if (!matrix.empty()) {
    for (int axis = 0; axis < 3; ++axis)
      for (int r = 0; r < 3; ++r) dir[axis][r] = matrix[std::size_t(axis * 3 + r)];
  } else {
    orientationDirections(h, dir);
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!(spacing[std::size_t(axis)] > 0.0))
      h.fail("ElementSpacing " + numberText(spacing[std::size_t(axis)]) + " is not positive");
    for (int r = 0; r < 3; ++r) out.m[r][axis] = dir[axis][r] * spacing[std::size_t(axis)];
  }
  out.centre0 = glm::dvec3(offset[0], offset[1], offset[2]);

  // The data's place as a NRRD header would say it: LOCAL data follows the header.
  nrrd::Header where;
  where.path = path;
  where.headerBytes = h.headerBytes;
  const std::string file = *h.field({"elementdatafile"});
  if (file.empty()) h.fail("ElementDataFile names no file");
  if (file != "LOCAL") where.fields["datafile"] = file;
  if (const std::string* skip = h.field({"headersize"})) where.fields["byteskip"] = *skip;
  const bool compressed = flag(h, {"compresseddata"});
  const bool bigEndian = flag(h, {"binarydatabyteordermsb", "elementbyteordermsb"});
  const std::uint64_t expected = voxels * scalar.bytes;
  const nrrd::DataLocation at = nrrd::locateData(where, expected, compressed, allowOutsideData);
  refuseOverVolumeMemory(path, v.sizes, scalar.bytes);
  std::vector<unsigned char> bytes;
  if (compressed) {
    bytes = nrrd::inflateData(at, expected);
  } else {
    bytes.resize(expected);
    std::ifstream data = nrrd::openData(at);
    if (!data.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size())))
      throw InputError(at.shown + ": read failed in the data");
  }
  setVolumeValues(scalar, bigEndian, std::move(bytes), voxels, v);
  return out;
}

}  // namespace osteon::geometry::io
