#include "support/dicom_series.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <gdcmAttribute.h>
#include <gdcmImageChangeTransferSyntax.h>
#include <gdcmImageWriter.h>
#include <gdcmReader.h>
#include <gdcmTrace.h>
#include <gdcmUIDGenerator.h>
#include <gdcmWriter.h>
#include <stdexcept>

namespace osteon::test {

namespace {

gdcm::TransferSyntax syntaxNamed(const std::string& name) {
  if (name == "jpegls") return gdcm::TransferSyntax::JPEGLSLossless;
  if (name == "jpeg2000") return gdcm::TransferSyntax::JPEG2000Lossless;
  if (name == "jpeglossless") return gdcm::TransferSyntax::JPEGLosslessProcess14_1;
  if (name == "jpegbaseline") return gdcm::TransferSyntax::JPEGBaselineProcess1;
  if (name == "rle") return gdcm::TransferSyntax::RLELossless;
  throw std::runtime_error("no transfer syntax " + name);
}

template <typename T>
std::vector<char> bytesOf(const std::vector<std::int32_t>& values) {
  std::vector<char> out(values.size() * sizeof(T));
  for (std::size_t i = 0; i < values.size(); ++i) {
    const T v = static_cast<T>(values[i]);
    std::memcpy(&out[i * sizeof(T)], &v, sizeof(T));
  }
  return out;
}

}  // namespace

void writeDicomSlice(const std::string& path, const DicomSlice& s) {
  gdcm::Trace::SetWarning(false);
  gdcm::ImageWriter writer;
  // GDCM's images are reference-counted: one on the stack would be freed twice.
  gdcm::SmartPointer<gdcm::Image> owned = new gdcm::Image;
  gdcm::Image& image = *owned;
  image.SetNumberOfDimensions(2);
  image.SetDimension(0, unsigned(s.columns));
  image.SetDimension(1, unsigned(s.rows));
  image.SetPixelFormat(s.eightBit   ? gdcm::PixelFormat::UINT8
                       : s.isSigned ? gdcm::PixelFormat::INT16
                                    : gdcm::PixelFormat::UINT16);
  image.SetPhotometricInterpretation(gdcm::PhotometricInterpretation::MONOCHROME2);
  image.SetSpacing(0, s.pixelSpacing[1]);
  image.SetSpacing(1, s.pixelSpacing[0]);
  image.SetOrigin(s.position);
  image.SetDirectionCosines(s.orientation);
  image.SetSlope(s.slope);
  image.SetIntercept(s.intercept);
  const std::vector<char> bytes = s.eightBit   ? bytesOf<std::uint8_t>(s.stored)
                                  : s.isSigned ? bytesOf<std::int16_t>(s.stored)
                                               : bytesOf<std::uint16_t>(s.stored);
  gdcm::DataElement pixels(gdcm::Tag(0x7fe0, 0x0010));
  pixels.SetByteValue(bytes.data(), gdcm::VL(std::uint32_t(bytes.size())));
  image.SetDataElement(pixels);
  image.SetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);
  if (!s.transferSyntax.empty()) {
    gdcm::ImageChangeTransferSyntax change;
    change.SetTransferSyntax(syntaxNamed(s.transferSyntax));
    change.SetInput(image);
    if (!change.Change()) throw std::runtime_error("GDCM cannot compress to " + s.transferSyntax);
    writer.SetImage(change.GetOutput());
  } else {
    writer.SetImage(image);
  }
  gdcm::DataSet& ds = writer.GetFile().GetDataSet();
  gdcm::Attribute<0x0008, 0x0016> sop;
  sop.SetValue(s.sopClass);
  ds.Replace(sop.GetAsDataElement());
  gdcm::UIDGenerator uid;
  gdcm::Attribute<0x0008, 0x0018> instance;
  instance.SetValue(uid.Generate());
  ds.Replace(instance.GetAsDataElement());
  gdcm::Attribute<0x0008, 0x0060> modality;
  modality.SetValue(s.sopClass == "1.2.840.10008.5.1.4.1.1.2" ? "CT" : "OT");
  ds.Replace(modality.GetAsDataElement());
  gdcm::Attribute<0x0020, 0x000e> series;
  series.SetValue(s.seriesUid);
  ds.Replace(series.GetAsDataElement());
  writer.SetFileName(path.c_str());
  if (!writer.Write()) throw std::runtime_error("GDCM cannot write " + path);
  // A 2-D image keeps two coordinates of its origin (GDCM writes z = 0; a 3-D one of one frame
  // is written as a multi-frame image): the position is set in the file afterwards.
  gdcm::Reader reader;
  reader.SetFileName(path.c_str());
  if (!reader.Read()) throw std::runtime_error("GDCM cannot read back " + path);
  gdcm::Attribute<0x0020, 0x0032> position;
  for (unsigned i = 0; i < 3; ++i) position.SetValue(s.position[i], i);
  reader.GetFile().GetDataSet().Replace(position.GetAsDataElement());
  reader.GetFile().GetDataSet().Replace(sop.GetAsDataElement());  // ImageWriter's own otherwise
  gdcm::Writer rewriter;
  rewriter.SetFile(reader.GetFile());
  rewriter.SetFileName(path.c_str());
  if (!rewriter.Write()) throw std::runtime_error("GDCM cannot write " + path);
}

void writeDicomMultiFrame(const std::string& path, const DicomSlice& s, int frames,
                          double sliceSpacingMm) {
  gdcm::Trace::SetWarning(false);
  gdcm::ImageWriter writer;
  gdcm::Image& image = writer.GetImage();
  image.SetNumberOfDimensions(3);
  image.SetDimension(0, unsigned(s.columns));
  image.SetDimension(1, unsigned(s.rows));
  image.SetDimension(2, unsigned(frames));
  image.SetPixelFormat(gdcm::PixelFormat::INT16);
  image.SetPhotometricInterpretation(gdcm::PhotometricInterpretation::MONOCHROME2);
  const double spacing[3] = {s.pixelSpacing[1], s.pixelSpacing[0], sliceSpacingMm};
  image.SetSpacing(spacing);
  image.SetOrigin(s.position);
  image.SetDirectionCosines(s.orientation);
  std::vector<std::int32_t> values;
  for (int k = 0; k < frames; ++k)
    for (std::int32_t v : s.stored) values.push_back(v + 100 * k);
  const std::vector<char> bytes = bytesOf<std::int16_t>(values);
  gdcm::DataElement pixels(gdcm::Tag(0x7fe0, 0x0010));
  pixels.SetByteValue(bytes.data(), gdcm::VL(std::uint32_t(bytes.size())));
  image.SetDataElement(pixels);
  image.SetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);
  gdcm::Attribute<0x0008, 0x0016> sop;
  sop.SetValue("1.2.840.10008.5.1.4.1.1.2.1");  // enhanced CT image storage
  writer.GetFile().GetDataSet().Replace(sop.GetAsDataElement());
  writer.SetFileName(path.c_str());
  if (!writer.Write()) throw std::runtime_error("GDCM cannot write " + path);
}

std::vector<DicomSlice> dicomStack(int count, double z0, double spacingMm, int columns, int rows) {
  std::vector<DicomSlice> out(std::size_t(count), DicomSlice{});
  for (int k = 0; k < count; ++k) {
    DicomSlice& s = out[std::size_t(k)];
    s.columns = columns;
    s.rows = rows;
    s.position[2] = z0 + k * spacingMm;
    s.stored.resize(std::size_t(s.columns * s.rows));
    for (int i = 0; i < s.columns * s.rows; ++i) s.stored[std::size_t(i)] = 100 * k + i - 1024;
  }
  return out;
}

}  // namespace osteon::test

namespace osteon::test {

void writeDicomVolume(const std::string& folder, const TestVolume& v,
                      const std::vector<double>& hu) {
  std::filesystem::create_directories(folder);
  for (int k = 0; k < v.sizes.z; ++k) {
    DicomSlice s;
    s.columns = v.sizes.x;
    s.rows = v.sizes.y;
    s.pixelSpacing[0] = s.pixelSpacing[1] = v.spacingMm;
    const glm::dvec3 p = v.firstCentreMm + glm::dvec3(0.0, 0.0, k * v.spacingMm);
    for (int a = 0; a < 3; ++a) s.position[a] = p[a];
    const std::size_t plane = std::size_t(v.sizes.x) * std::size_t(v.sizes.y);
    for (std::size_t i = 0; i < plane; ++i)
      s.stored.push_back(std::int32_t(std::lround(hu.at(std::size_t(k) * plane + i))));
    writeDicomSlice(folder + "/S" + std::to_string(k) + ".dcm", s);
  }
}

}  // namespace osteon::test
