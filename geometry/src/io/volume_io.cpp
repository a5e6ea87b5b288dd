// Which reader a volume's path goes to, and NRRD volumes (users' NRRDs: any scalar type, LPS
// or RAS, any affine), handed to placeVolume like every reader's.
#include "osteon/geometry/io/volume_io.h"

#include <algorithm>
#include <cctype>
#include <fstream>

#include "io/huge_pages.h"
#include "io/nrrd_header.h"
#include "io/volume_place.h"
#include "io/volume_readers.h"
#include "osteon/core/error.h"
#include "osteon/core/option_error.h"

namespace osteon::geometry {

namespace {

using nrrd::excerpt;
using nrrd::parseNumbers;
using nrrd::trim;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// The NRRD's affine in LPS: `space` with `space directions` (and `space origin`), or
// `spacings` alone; RAS turned to LPS.
void nrrdAffine(const nrrd::Header& h, double m[3][3], glm::dvec3& centre0) {
  const std::string* space = h.field("space");
  const std::string* spacings = h.field("spacings");
  if (!space && !spacings)
    h.fail("no spacing ('space' with 'space directions', or 'spacings' field)");
  const std::string s = space ? lower(trim(*space)) : "lps";
  if (s != "left-posterior-superior" && s != "lps" && s != "right-anterior-superior" &&
      s != "ras") {
    h.fail("space " + excerpt(s) + " is not supported (LPS or RAS)");
  }
  const bool ras = s == "right-anterior-superior" || s == "ras";
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[r][c] = r == c ? 1.0 : 0.0;
  }
  centre0 = glm::dvec3(0.0);
  if (!space) {
    std::vector<double> sp;
    if (!parseNumbers(*spacings, sp) || sp.size() != 3 || !(sp[0] > 0) || !(sp[1] > 0) ||
        !(sp[2] > 0)) {
      h.fail("spacings " + excerpt(*spacings) + " are not three positive numbers");
    }
    for (std::size_t a = 0; a < 3; ++a) m[a][a] = sp[a];
  } else if (const std::string* dirs = h.field("spacedirections")) {
    std::vector<double> d;
    if (!parseNumbers(*dirs, d) || d.size() != 9)
      h.fail("space directions " + excerpt(*dirs) + " are not three 3-vectors");
    for (std::size_t axis = 0; axis < 3; ++axis) {
      for (std::size_t r = 0; r < 3; ++r) m[r][axis] = d[axis * 3 + r];
    }
  } else {
    h.fail("'space' without 'space directions'");
  }
  if (const std::string* origin = h.field("spaceorigin")) {
    std::vector<double> o;
    if (!parseNumbers(*origin, o) || o.size() != 3)
      h.fail("space origin " + excerpt(*origin) + " is not a 3-vector");
    centre0 = glm::dvec3(o[0], o[1], o[2]);
  }
  if (ras) {
    for (int axis = 0; axis < 3; ++axis) {
      m[0][axis] = -m[0][axis];
      m[1][axis] = -m[1][axis];
    }
    centre0.x = -centre0.x;
    centre0.y = -centre0.y;
  }
}

RawVolume readNrrdVolume(const std::string& path, bool allowOutsideData) {
  const nrrd::Header h = nrrd::readHeader(path);
  RawVolume v;
  // osteon's own grid only by all it writes: a user's file with one osteon_* key is a volume.
  switch (nrrd::osteonFile(h)) {
    case nrrd::OsteonFile::Fill:
      v.osteonGrid = true;
      return v;
    case nrrd::OsteonFile::Density:
      h.fail(
          "an osteon density file (it goes with a grid's fill file): open the grid's .nrrd beside "
          "it, without '.density'");
    case nrrd::OsteonFile::None:
      break;
  }
  v.sizes = nrrd::readSizes(h);
  const nrrd::Layout layout = nrrd::readLayout(h);
  const nrrd::Scalar& scalar = layout.scalar;
  v.type = scalar.name;
  v.integer = scalar.integer;
  v.isSigned = scalar.isSigned;
  double m[3][3];
  glm::dvec3 centre0;
  nrrdAffine(h, m, centre0);
  const std::uint64_t count =
      std::uint64_t(v.sizes.x) * std::uint64_t(v.sizes.y) * std::uint64_t(v.sizes.z);
  const std::uint64_t expected = count * scalar.bytes;
  // Where the data lies and how long it is, known before a byte of it is read.
  const nrrd::DataLocation at = nrrd::locateData(h, expected, layout.gzip, allowOutsideData);
  refuseOverVolumeMemory(path, v.sizes, scalar.bytes);
  std::vector<unsigned char> raw;
  if (layout.gzip) {
    raw = nrrd::inflateData(at, expected);
  } else {
    raw.reserve(expected);
    adviseHugePages(raw.data(), expected);
    raw.resize(expected);
    std::ifstream data = nrrd::openData(at);
    if (!data.read(reinterpret_cast<char*>(raw.data()), std::streamsize(raw.size()))) {
      throw InputError(at.shown + ": read failed in the data");
    }
  }
  setVolumeValues(scalar, layout.bigEndian, std::move(raw), count, v);
  placeVolume(path, m, centre0, v);
  return v;
}

}  // namespace

bool isVolumePath(const std::string& path) {
  const std::string p = lower(path);
  return endsWith(p, ".nrrd") || endsWith(p, ".nhdr") || endsWith(p, ".nii") ||
         endsWith(p, ".nii.gz") || io::isMetaImagePath(path) || io::isDicomPath(path);
}

std::string volumeFormat(const std::string& path) {
  const std::string p = lower(path);
  if (endsWith(p, ".nii") || endsWith(p, ".nii.gz")) return "nifti";
  if (io::isMetaImagePath(path)) return "metaimage";
  // By extension first: a folder named x.nrrd is a NRRD name that is not a file.
  if (endsWith(p, ".nrrd") || endsWith(p, ".nhdr")) return "nrrd";
  if (io::isDicomPath(path)) return "dicom";
  return "nrrd";
}

RawVolume readRawVolume(const std::string& path, bool allowOutsideData) {
  const std::string p = lower(path);
  if (endsWith(p, ".nii") || endsWith(p, ".nii.gz")) return readNiftiVolume(path);
  return readNrrdVolume(path, allowOutsideData);
}

RawVolume readRawVolume(const std::string& path, const VolumeOptions& options) {
  const std::string format = volumeFormat(path);
  if (!options.series.empty() && format != "dicom") {
    throw OptionError("volume.series", options.series, "only for DICOM; " + path + " is " + format);
  }
  if (format != "metaimage" && format != "dicom")
    return readRawVolume(path, options.allowOutsideData);
  io::StoredVolume s = format == "dicom" ? io::readDicom(path, options.series)
                                         : io::readMetaImage(path, options.allowOutsideData);
  placeVolume(path, s.m, s.centre0, s.volume);
  return std::move(s.volume);
}

}  // namespace osteon::geometry
