// libosteon_dicom.so: CT series read with GDCM, behind the C interface of dicom_plugin_abi.h.
// GDCM decodes what its Debian build was built with: uncompressed, JPEG (baseline, extended,
// lossless), JPEG-LS (CharLS), JPEG 2000 (OpenJPEG) and RLE.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <gdcmDictEntry.h>
#include <gdcmDicts.h>
#include <gdcmExplicitDataElement.h>
#include <gdcmFileMetaInformation.h>
#include <gdcmGlobal.h>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmImplicitDataElement.h>
#include <gdcmReader.h>
#include <gdcmSequenceOfFragments.h>
#include <gdcmSequenceOfItems.h>
#include <gdcmTrace.h>
#include <gdcmTransferSyntax.h>
#include <gdcmVersion.h>
#include <string>
#include <vector>

#include "dicom_image.h"
#include "dicom_plugin_abi.h"
#include "dicom_series.h"

namespace osteon::dicom {

namespace {

// CT Image Storage, Enhanced CT Image Storage, Legacy Converted Enhanced CT Image Storage.
bool isCt(const std::string& sopClass) {
  return sopClass == "1.2.840.10008.5.1.4.1.1.2" || sopClass == "1.2.840.10008.5.1.4.1.1.2.1" ||
         sopClass == "1.2.840.10008.5.1.4.1.1.2.2";
}

std::string name(const std::string& file) {
  return std::filesystem::path(file).filename().string();
}

// GDCM reads a pixel block cut short as if zeros followed ("incomplete pixel data"): the file
// must be as long as its elements say.
void refuseTruncated(const gdcm::File& f, const std::string& file) {
  const bool implicit = f.GetHeader().GetDataSetTransferSyntax().IsImplicit();
  const std::uint64_t dataSet = implicit ? f.GetDataSet().GetLength<gdcm::ImplicitDataElement>()
                                         : f.GetDataSet().GetLength<gdcm::ExplicitDataElement>();
  // The header's length counts the 128-byte preamble and "DICM" even when a file has none.
  const std::uint64_t missingPreamble = f.GetHeader().GetPreamble().IsEmpty() ? 132 : 0;
  const std::uint64_t expected = f.GetHeader().GetFullLength() + dataSet - missingPreamble;
  std::error_code ec;
  const std::uint64_t size = std::filesystem::file_size(file, ec);
  if (!ec && size < expected) {
    fail(name(file) + ": truncated: the file holds " + std::to_string(size) +
         " bytes, its elements need " + std::to_string(expected) + " (a cut pixel block?)");
  }
}

// Six finite numbers in a DS element (an image orientation: a row and a column direction).
bool sixNumbers(const gdcm::DataSet& ds, const gdcm::Tag& tag) {
  if (!ds.FindDataElement(tag)) return false;
  const gdcm::ByteValue* bv = ds.GetDataElement(tag).GetByteValue();
  if (!bv || bv->GetLength() == 0) return false;
  std::string text(bv->GetPointer(), bv->GetLength());
  std::replace(text.begin(), text.end(), '\\', ' ');
  const char* p = text.c_str();
  int count = 0;
  for (char* end = nullptr;; p = end) {
    const double v = std::strtod(p, &end);
    if (end == p) break;
    if (!std::isfinite(v)) return false;
    ++count;
  }
  return count == 6;
}

// The first item of a sequence's first item's plane orientation holds one (functional groups).
bool orientationInGroups(const gdcm::DataSet& ds, const gdcm::Tag& groups) {
  const gdcm::Tag planeOrientation(0x0020, 0x9116);
  for (const gdcm::Tag& t : {groups, planeOrientation}) {
    if (!ds.FindDataElement(t)) return false;
    const gdcm::SmartPointer<gdcm::SequenceOfItems> sq = ds.GetDataElement(t).GetValueAsSQ();
    if (!sq || sq->GetNumberOfItems() == 0) return false;
    if (t == planeOrientation) return sixNumbers(sq->GetItem(1).GetNestedDataSet(), {0x20, 0x37});
    return orientationInGroups(sq->GetItem(1).GetNestedDataSet(), planeOrientation);
  }
  return false;
}

// GDCM asserts, aborting the process, when it reads an element of a known tag whose explicit VR
// its dictionary does not allow (gdcm::Attribute::SetFromDataElement): every element of the data
// set and of its items is compared with the dictionary first.
void refuseForeignVrs(const gdcm::DataSet& ds, const std::string& file, int depth) {
  const gdcm::Dicts& dicts = gdcm::Global::GetInstance().GetDicts();
  for (auto it = ds.Begin(); it != ds.End(); ++it) {
    const gdcm::DataElement& de = *it;
    const gdcm::VR vr = de.GetVR();
    const gdcm::Tag& tag = de.GetTag();
    if (vr != gdcm::VR::INVALID && !tag.IsPrivate()) {
      const gdcm::VR expected = dicts.GetDictEntry(tag).GetVR();
      if (expected != gdcm::VR::INVALID && !expected.Compatible(vr)) {
        char at[16];
        std::snprintf(at, sizeof at, "(%04x,%04x)", unsigned(tag.GetGroup()),
                      unsigned(tag.GetElement()));
        fail(name(file) + ": element " + at + " has VR " + gdcm::VR::GetVRString(vr) +
             ", which its tag does not allow");
      }
    }
    if (vr != gdcm::VR::SQ || depth >= 16) continue;
    const gdcm::SmartPointer<gdcm::SequenceOfItems> sq = de.GetValueAsSQ();
    if (!sq) continue;
    for (gdcm::SequenceOfItems::SizeType i = 1; i <= sq->GetNumberOfItems(); ++i)
      refuseForeignVrs(sq->GetItem(i).GetNestedDataSet(), file, depth + 1);
  }
}

// What GDCM would assert on, aborting the process, refused from the data set alone before GDCM
// reads it as an image: an element whose VR its tag does not allow, and an enhanced CT file
// with no image orientation in any place GDCM looks for one (its functional groups, or the
// data set itself).
void refuseEnhancedWithoutOrientation(const std::string& file) {
  gdcm::Reader plain;
  plain.SetFileName(file.c_str());
  if (!plain.Read()) fail(name(file) + ": GDCM cannot read it as a DICOM file (truncated?)");
  const gdcm::DataSet& ds = plain.GetFile().GetDataSet();
  refuseForeignVrs(ds, file, 0);
  const gdcm::Tag sopClass(0x0008, 0x0016);
  std::string sop;
  if (ds.FindDataElement(sopClass)) {
    if (const gdcm::ByteValue* bv = ds.GetDataElement(sopClass).GetByteValue())
      sop.assign(bv->GetPointer(), bv->GetLength());
  }
  while (!sop.empty() && (sop.back() == '\0' || sop.back() == ' ')) sop.pop_back();
  const bool enhanced =
      sop == "1.2.840.10008.5.1.4.1.1.2.1" || sop == "1.2.840.10008.5.1.4.1.1.2.2";
  const bool groups = ds.FindDataElement(gdcm::Tag(0x5200, 0x9229)) ||
                      ds.FindDataElement(gdcm::Tag(0x5200, 0x9230));
  if (!enhanced && !groups) return;
  if (orientationInGroups(ds, {0x5200, 0x9229}) || orientationInGroups(ds, {0x5200, 0x9230}) ||
      sixNumbers(ds, {0x0020, 0x0037}))
    return;
  fail(name(file) +
       ": a multi-frame CT without an image orientation (0020,0037), shared, per "
       "frame or in the data set");
}

// One file holding every slice (Enhanced CT): GDCM gives its geometry from the frames.
void readMultiFrame(const Slice& slice, const Output& out) {
  gdcm::ImageReader reader;
  readImage(reader, slice.file);
  const gdcm::Image& image = reader.GetImage();
  const Pixels p = pixelsOf(image, slice.file);
  osteon_dicom_volume& v = *out.volume;
  for (int a = 0; a < 3; ++a) v.sizes[a] = int(image.GetDimension(unsigned(a)));
  const double* d = image.GetDirectionCosines();
  const double row[3] = {d[0], d[1], d[2]}, col[3] = {d[3], d[4], d[5]};
  const double normal[3] = {row[1] * col[2] - row[2] * col[1], row[2] * col[0] - row[0] * col[2],
                            row[0] * col[1] - row[1] * col[0]};
  for (int r = 0; r < 3; ++r) {
    v.m[r][0] = row[r] * image.GetSpacing(0);
    v.m[r][1] = col[r] * image.GetSpacing(1);
    v.m[r][2] = normal[r] * image.GetSpacing(2);
    v.centre0[r] = image.GetOrigin(unsigned(r));
  }
  std::strcpy(v.type, p.type);
  v.slope = image.GetSlope();
  v.intercept = image.GetIntercept();
  v.slices_rescaled = 0;
  const std::size_t bytes =
      std::size_t(v.sizes[0]) * std::size_t(v.sizes[1]) * std::size_t(v.sizes[2]) * p.bytes;
  refuseImplausible(reader.GetFile(), slice.file, bytes);
  char* to = out.allocate(bytes);
  // Every frame decodes in one call: the caller is told how long a step to allow.
  out.tick(std::uint64_t(v.sizes[0]) * std::uint64_t(v.sizes[1]) * std::uint64_t(v.sizes[2]));
  decode(image, slice.file, to, bytes);
}

// GDCM's warnings and errors go to stderr; osteon says what went wrong in one line itself.
void quiet() {
  gdcm::Trace::SetWarning(false);
  gdcm::Trace::SetError(false);
  gdcm::Trace::SetDebug(false);
}

// `text` into a fixed field of `size` bytes, cut short if need be, always terminated.
template <std::size_t N>
void copyField(char (&to)[N], const std::string& text) {
  const std::size_t n = std::min(text.size(), N - 1);
  std::memcpy(to, text.data(), n);
  to[n] = '\0';
}

int failed(const Failure& f, char* errbuf, std::size_t errlen) {
  if (errlen > 0) {
    const std::size_t n = std::min(f.reason.size(), errlen - 1);
    std::memcpy(errbuf, f.reason.data(), n);
    errbuf[n] = '\0';
  }
  return f.code;
}

}  // namespace

Pixels pixelsOf(const gdcm::Image& image, const std::string& file) {
  const gdcm::PixelFormat pf = image.GetPixelFormat();
  if (pf.GetSamplesPerPixel() != 1)
    fail(name(file) + ": " + std::to_string(pf.GetSamplesPerPixel()) +
         " samples per pixel (colour), not a grey CT slice");
  Pixels p;
  switch (pf.GetScalarType()) {
    case gdcm::PixelFormat::UINT8:
      p = {"uint8", 1, false};
      break;
    case gdcm::PixelFormat::INT8:
      p = {"int8", 1, true};
      break;
    case gdcm::PixelFormat::UINT12:
    case gdcm::PixelFormat::UINT16:
      p = {"uint16", 2, false};
      break;
    case gdcm::PixelFormat::INT12:
    case gdcm::PixelFormat::INT16:
      p = {"int16", 2, true};
      break;
    case gdcm::PixelFormat::UINT32:
      p = {"uint32", 4, false};
      break;
    case gdcm::PixelFormat::INT32:
      p = {"int32", 4, true};
      break;
    default:
      fail(name(file) + ": pixels of " + pf.GetScalarTypeAsString() + " are not supported");
  }
  p.bitsStored = pf.GetBitsStored();
  p.bitsAllocated = pf.GetBitsAllocated();
  return p;
}

void readImage(gdcm::ImageReader& reader, const std::string& file) {
  refuseEnhancedWithoutOrientation(file);
  reader.SetFileName(file.c_str());
  if (!reader.Read()) fail(name(file) + ": GDCM cannot read it as a DICOM image (truncated?)");
  refuseTruncated(reader.GetFile(), file);
}

// The pixel data must be able to hold the image its header describes, checked before the values
// are allocated: native data at its full length, compressed data within 100000:1 (far past what
// JPEG-LS makes of a blank slice), so a small file cannot ask for gigabytes.
void refuseImplausible(const gdcm::File& f, const std::string& file, std::uint64_t bytes) {
  const gdcm::Tag pixelData(0x7fe0, 0x0010);
  if (!f.GetDataSet().FindDataElement(pixelData)) fail(name(file) + ": no pixel data");
  const gdcm::DataElement& e = f.GetDataSet().GetDataElement(pixelData);
  if (const gdcm::ByteValue* bv = e.GetByteValue()) {
    if (bv->GetLength() < bytes) {
      fail(name(file) + ": truncated: " + std::to_string(bv->GetLength()) +
           " bytes of pixel data, its size needs " + std::to_string(bytes));
    }
  } else if (const gdcm::SequenceOfFragments* sf = e.GetSequenceOfFragments()) {
    if (bytes / 100000 > sf->ComputeByteLength()) {
      fail(name(file) + ": " + std::to_string(sf->ComputeByteLength()) +
           " bytes of compressed pixel data cannot hold the " + std::to_string(bytes) +
           " bytes its size needs");
    }
  }
}

// Decodes one image's pixels into `to` (exactly `bytes`).
void decode(const gdcm::Image& image, const std::string& file, char* to, std::size_t bytes) {
  if (image.GetBufferLength() != bytes) {
    fail(name(file) + ": its pixel data holds " + std::to_string(image.GetBufferLength()) +
         " bytes, the other slices " + std::to_string(bytes));
  }
  if (!image.GetBuffer(to)) {
    fail(name(file) + ": cannot decode its pixel data (transfer syntax " +
         image.GetTransferSyntax().GetString() + "; truncated or corrupt?)");
  }
}

}  // namespace osteon::dicom

using namespace osteon::dicom;

extern "C" {

__attribute__((visibility("default"))) int osteon_dicom_abi(void) {
  return OSTEON_DICOM_ABI;
}

__attribute__((visibility("default"))) const char* osteon_dicom_library_version(void) {
  return gdcm::Version::GetVersion();
}

__attribute__((visibility("default"))) int osteon_dicom_read(
    const char* path, const char* series, osteon_dicom_volume* out, osteon_dicom_alloc_fn alloc,
    osteon_dicom_progress_fn progress, void* context, char* errbuf, size_t errlen) {
  quiet();
  try {
    const Output output{out, alloc, progress, context};
    const std::vector<Series> all = scanSeries(path, [&] { output.tick(); });
    const Series& chosen = pickSeries(all, series ? series : "");
    if (!isCt(chosen.sopClass)) {
      fail("series " + chosen.uid + " is of SOP class " + chosen.sopClass +
           ", not CT image storage (1.2.840.10008.5.1.4.1.1.2)");
    }
    copyField(out->series_uid, chosen.uid);
    copyField(out->series_description, chosen.description);
    if (chosen.slices.size() == 1 && chosen.slices.front().frames > 1) {
      readMultiFrame(chosen.slices.front(), output);
      return 0;
    }
    const Stack stack = stackSlices(chosen);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) out->m[r][c] = stack.m[r][c];
      out->centre0[r] = stack.centre0[r];
    }
    readSeries(stack, output);
    return 0;
  } catch (const Failure& f) {
    return failed(f, errbuf, errlen);
  } catch (const std::exception& e) {
    return failed(Failure{2, std::string("GDCM failed: ") + e.what()}, errbuf, errlen);
  }
}

__attribute__((visibility("default"))) int osteon_dicom_list(const char* path,
                                                             osteon_dicom_alloc_fn alloc,
                                                             osteon_dicom_progress_fn progress,
                                                             void* context, char* errbuf,
                                                             size_t errlen) {
  quiet();
  try {
    std::string text;
    const Output output{nullptr, alloc, progress, context};
    for (const Series& s : scanSeries(path, [&] { output.tick(); })) {
      text += s.uid + "\t" + std::to_string(s.slices.size()) + "\t" + s.description + "\n";
    }
    char* to = static_cast<char*>(alloc(context, text.size() + 1));
    if (!to) return failed(Failure{3, "no memory"}, errbuf, errlen);
    std::memcpy(to, text.c_str(), text.size() + 1);
    return 0;
  } catch (const Failure& f) {
    return failed(f, errbuf, errlen);
  } catch (const std::exception& e) {
    return failed(Failure{2, std::string("GDCM failed: ") + e.what()}, errbuf, errlen);
  }
}

}  // extern "C"
