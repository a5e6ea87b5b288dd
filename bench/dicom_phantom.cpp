// A CT phantom as a DICOM series, written with GDCM: an ellipsoidal bone (a cortical shell of
// about 1200 HU around cancellous bone of about 350 HU, clear of the default 300 HU iso) in
// air (-1000 HU), int16 slices with a little fixed-seed noise, plain or compressed. For timing
// `osteon mesh FOLDER` on a series of clinical size (docs/performance.md, Volumes).
//   osteon_bench_dicom_phantom FOLDER [plain|jpegls|jpeg2000|rle] [columns rows slices]
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <gdcmAttribute.h>
#include <gdcmImageChangeTransferSyntax.h>
#include <gdcmImageWriter.h>
#include <gdcmReader.h>
#include <gdcmTrace.h>
#include <gdcmUIDGenerator.h>
#include <gdcmWriter.h>
#include <string>
#include <vector>

namespace {

constexpr double kSpacingMm = 0.7;

struct Size {
  int columns = 512, rows = 512, slices = 350;
};

// Slice k's stored values (HU, slope 1, intercept 0), row after row.
std::vector<std::int16_t> sliceValues(const Size& n, int k, std::uint32_t& seed) {
  std::vector<std::int16_t> values(std::size_t(n.columns) * std::size_t(n.rows));
  const double cx = 0.5 * n.columns, cy = 0.5 * n.rows, cz = 0.5 * n.slices;
  const double ax = 0.38 * n.columns, ay = 0.3 * n.rows, az = 0.45 * n.slices;
  const double shellVoxels = 8.0;
  for (int y = 0; y < n.rows; ++y) {
    for (int x = 0; x < n.columns; ++x) {
      const double dx = (x - cx) / ax, dy = (y - cy) / ay, dz = (k - cz) / az;
      const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
      // The shell's inner surface: the ellipsoid shrunk by shellVoxels along its shortest axis.
      const double inner = 1.0 - shellVoxels / std::min(ax, std::min(ay, az));
      const double hu = r > 1.0 ? -1000.0 : r > inner ? 1200.0 : 350.0;
      seed = seed * 1664525u + 1013904223u;
      const int noise = int((seed >> 16) % 41) - 20;
      values[std::size_t(y) * std::size_t(n.columns) + std::size_t(x)] =
          std::int16_t(std::lround(hu) + noise);
    }
  }
  return values;
}

gdcm::TransferSyntax syntaxNamed(const std::string& name) {
  if (name == "jpegls") return gdcm::TransferSyntax::JPEGLSLossless;
  if (name == "jpeg2000") return gdcm::TransferSyntax::JPEG2000Lossless;
  if (name == "rle") return gdcm::TransferSyntax::RLELossless;
  return gdcm::TransferSyntax::ExplicitVRLittleEndian;
}

template <uint16_t G, uint16_t E>
void put(gdcm::DataSet& ds, const std::string& value) {
  gdcm::Attribute<G, E> a;
  a.SetValue(value);
  ds.Replace(a.GetAsDataElement());
}

bool writeSlice(const std::string& path, const Size& n, int k, const std::string& syntax,
                const std::string& seriesUid, const std::vector<std::int16_t>& values) {
  gdcm::SmartPointer<gdcm::Image> owned = new gdcm::Image;
  gdcm::Image& image = *owned;
  image.SetNumberOfDimensions(2);
  image.SetDimension(0, unsigned(n.columns));
  image.SetDimension(1, unsigned(n.rows));
  image.SetPixelFormat(gdcm::PixelFormat::INT16);
  image.SetPhotometricInterpretation(gdcm::PhotometricInterpretation::MONOCHROME2);
  image.SetSpacing(0, kSpacingMm);
  image.SetSpacing(1, kSpacingMm);
  const double cosines[6] = {1, 0, 0, 0, 1, 0};
  image.SetDirectionCosines(cosines);
  gdcm::DataElement pixels(gdcm::Tag(0x7fe0, 0x0010));
  pixels.SetByteValue(reinterpret_cast<const char*>(values.data()),
                      gdcm::VL(std::uint32_t(values.size() * sizeof(std::int16_t))));
  image.SetDataElement(pixels);
  image.SetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);
  gdcm::ImageWriter writer;
  // The SOP class before writing: ImageWriter writes a CT's position, orientation and spacing.
  put<0x0008, 0x0016>(writer.GetFile().GetDataSet(), "1.2.840.10008.5.1.4.1.1.2");
  gdcm::ImageChangeTransferSyntax change;
  if (syntax != "plain") {
    change.SetTransferSyntax(syntaxNamed(syntax));
    change.SetInput(image);
    if (!change.Change()) return false;
    writer.SetImage(change.GetOutput());
  } else {
    writer.SetImage(image);
  }
  writer.SetFileName(path.c_str());
  if (!writer.Write()) return false;
  // GDCM writes a 2-D image's origin with z = 0: position, class and series set afterwards.
  gdcm::Reader reader;
  reader.SetFileName(path.c_str());
  if (!reader.Read()) return false;
  gdcm::DataSet& ds = reader.GetFile().GetDataSet();
  gdcm::Attribute<0x0020, 0x0032> position;
  const double at[3] = {0.0, 0.0, k * kSpacingMm};
  for (unsigned i = 0; i < 3; ++i) position.SetValue(at[i], i);
  ds.Replace(position.GetAsDataElement());
  put<0x0008, 0x0016>(ds, "1.2.840.10008.5.1.4.1.1.2");  // ImageWriter's own otherwise
  put<0x0008, 0x0060>(ds, "CT");
  put<0x0008, 0x103e>(ds, "phantom " + syntax);
  put<0x0020, 0x000e>(ds, seriesUid);
  gdcm::Writer rewriter;
  rewriter.SetFile(reader.GetFile());
  rewriter.SetFileName(path.c_str());
  return rewriter.Write();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 6) {
    std::fprintf(stderr, "usage: %s FOLDER plain|jpegls|jpeg2000|rle [columns rows slices]\n",
                 argv[0]);
    return 2;
  }
  const std::string folder = argv[1], syntax = argv[2];
  Size n;
  if (argc == 6) n = {std::atoi(argv[3]), std::atoi(argv[4]), std::atoi(argv[5])};
  gdcm::Trace::SetWarning(false);
  std::filesystem::create_directories(folder);
  gdcm::UIDGenerator uid;
  const std::string seriesUid = uid.Generate();
  std::uint32_t seed = 12345u;
  for (int k = 0; k < n.slices; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "/S%04d.dcm", k);
    if (!writeSlice(folder + name, n, k, syntax, seriesUid, sliceValues(n, k, seed))) {
      std::fprintf(stderr, "cannot write %s%s\n", folder.c_str(), name);
      return 1;
    }
  }
  std::printf("%s: %d slices of %d x %d, %s, series %s\n", folder.c_str(), n.slices, n.columns,
              n.rows, syntax.c_str(), seriesUid.c_str());
  return 0;
}
