// DICOM series and MetaImage volumes through the commands that take a volume: a CT box written
// anisotropic (0.8 x 0.8 x 1.6 mm) and rotated 15 degrees about z, as a JPEG-LS DICOM series
// with shuffled file names and as a .mha, meshes where the scanner put it and drills; series
// are listed and picked; wrong picks are one-line refusals.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/io/mesh_io.h"
#include "support/cli_fixture.h"
#include "support/dicom_series.h"
#include "support/files.h"

namespace osteon {
namespace {

namespace fs = std::filesystem;

constexpr int kPixels = 24, kSlices = 16, kLo = 7, kHi = 17, kSliceLo = 4, kSliceHi = 12;
constexpr double kPixelMm = 0.8, kSliceMm = 1.6, kAngle = 15.0 * M_PI / 180.0;
const glm::dvec3 kFirstMm(-20.0, 5.0, 100.0);  // centre of the first voxel, LPS

glm::dvec3 rowDir() {
  return {std::cos(kAngle), std::sin(kAngle), 0.0};
}
glm::dvec3 colDir() {
  return {-std::sin(kAngle), std::cos(kAngle), 0.0};
}

// Where the box's centre lies in LPS: its index centre through the scanner's geometry.
glm::dvec3 boxCentreMm() {
  const double c = 0.5 * (kLo + kHi - 1), s = 0.5 * (kSliceLo + kSliceHi - 1);
  return kFirstMm + rowDir() * (c * kPixelMm) + colDir() * (c * kPixelMm) +
         glm::dvec3(0, 0, s * kSliceMm);
}

// 1200 HU inside the box, -1000 outside, stored as uint16 with intercept -1024.
// Or, `ball`, a ball of 8 mm radius about the same centre (a head for validate's portal-5).
std::int32_t stored(int x, int y, int k, bool ball = false) {
  const glm::dvec3 at = kFirstMm + rowDir() * (x * kPixelMm) + colDir() * (y * kPixelMm) +
                        glm::dvec3(0, 0, k * kSliceMm);
  const bool in = ball
                      ? glm::length(at - boxCentreMm()) < 8.0
                      : x >= kLo && x < kHi && y >= kLo && y < kHi && k >= kSliceLo && k < kSliceHi;
  return (in ? 1200 : -1000) + 1024;
}

class DicomMetaImageCliTest : public CliTest {
 protected:
  bool ball_ = false;  // write the ball, not the box
  // Slices first .. first + count - 1 of the stack, files named <uid>_<shuffled index>.
  std::string writeSeries(const std::string& name, const std::string& uid, int count,
                          int first = 0) {
    const std::string folder = path(name);
    fs::create_directories(folder);
    std::vector<int> order(std::size_t(count), 0);
    for (int i = 0; i < count; ++i) order[std::size_t(i)] = i;
    std::shuffle(order.begin(), order.end(), std::mt19937(11));
    for (int k = first; k < first + count; ++k) {
      test::DicomSlice s;
      s.columns = s.rows = kPixels;
      s.isSigned = false;
      s.intercept = -1024.0;
      s.seriesUid = uid;
      s.transferSyntax = "jpegls";
      s.pixelSpacing[0] = s.pixelSpacing[1] = kPixelMm;
      const glm::dvec3 r = rowDir(), c = colDir(), p = kFirstMm + glm::dvec3(0, 0, k * kSliceMm);
      const double o[6] = {r.x, r.y, r.z, c.x, c.y, c.z};
      std::copy(o, o + 6, s.orientation);
      for (int a = 0; a < 3; ++a) s.position[a] = p[a];
      for (int y = 0; y < kPixels; ++y)
        for (int x = 0; x < kPixels; ++x) s.stored.push_back(stored(x, y, k, ball_));
      test::writeDicomSlice(
          folder + "/" + uid + "_" + std::to_string(order[std::size_t(k - first)]), s);
    }
    return folder;
  }

  std::string writeMha(const std::string& name) {
    std::string data;
    for (int k = 0; k < kSlices; ++k) {
      for (int y = 0; y < kPixels; ++y) {
        for (int x = 0; x < kPixels; ++x) {
          const std::int16_t hu = std::int16_t(stored(x, y, k, ball_) - 1024);
          data.append(reinterpret_cast<const char*>(&hu), 2);
        }
      }
    }
    const glm::dvec3 r = rowDir(), c = colDir();
    std::ostringstream h;
    h.precision(17);
    h << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
      << "TransformMatrix = " << r.x << " " << r.y << " " << r.z << " " << c.x << " " << c.y << " "
      << c.z << " 0 0 1\nOffset = " << kFirstMm.x << " " << kFirstMm.y << " " << kFirstMm.z
      << "\nAnatomicalOrientation = RAI\nElementSpacing = " << kPixelMm << " " << kPixelMm << " "
      << kSliceMm << "\nDimSize = " << kPixels << " " << kPixels << " " << kSlices
      << "\nElementType = MET_SHORT\nElementDataFile = LOCAL\n";
    test::writeBytes(path(name), h.str() + data);
    return path(name);
  }

  // Meshes the volume and checks the mesh lies where the scanner put the box, with its volume.
  void expectMeshedInPlace(const std::string& volume, const std::string& format) {
    const CliRun run = osteon("mesh '" + volume + "' --json --out '" + path(format + ".ply") + "'");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json j = nlohmann::json::parse(run.out);
    EXPECT_EQ(j["volume"]["format"], format);
    EXPECT_EQ(j["volume"]["kind"], "ct");
    const geometry::TriangleMesh mesh = geometry::readMesh(path(format + ".ply"));
    const geometry::Aabb box = geometry::bounds(mesh);
    const glm::dvec3 centre = 0.5 * (box.minMm + box.maxMm), want = boxCentreMm();
    EXPECT_LT(glm::length(centre - want), kPixelMm)
        << format << " centre " << centre.x << " " << centre.y << " " << centre.z;
    const double boxMm3 = std::pow((kHi - kLo) * kPixelMm, 2) * (kSliceHi - kSliceLo) * kSliceMm;
    EXPECT_NEAR(geometry::signedVolumeMm3(mesh), boxMm3, 0.1 * boxMm3) << format;
  }

  void expectDrills(const std::string& volume, const std::string& out) {
    const glm::dvec3 c = boxCentreMm();
    std::string rows = "t,x,y,z,drill_on\n0," + std::to_string(c.x) + "," + std::to_string(c.y) +
                       "," + std::to_string(c.z + 15) + ",1\n2," + std::to_string(c.x) + "," +
                       std::to_string(c.y) + "," + std::to_string(c.z) + ",1\n";
    test::writeBytes(path(out + ".csv"), rows);
    const CliRun run = osteon("drill '" + volume + "' --voxel-size 0.8 --levels 0 --json --path '" +
                              path(out + ".csv") + "' --out-dir '" + path(out) + "'");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_GT(nlohmann::json::parse(run.out)["removed_volume_mm3"].get<double>(), 1.0);
  }
};

TEST_F(DicomMetaImageCliTest, AnObliqueAnisotropicSeriesMeshesWhereTheScannerPutIt) {
  const std::string folder = writeSeries("ct", "1.2.826.0.1.3680043.2.1125.7", kSlices);
  expectMeshedInPlace(folder, "dicom");
  expectDrills(folder, "drill_dicom");
  expectMeshedInPlace(writeMha("ct.mha"), "metaimage");
  expectDrills(path("ct.mha"), "drill_mha");
}

// Without --voxel-size a volume is drilled at its finest spacing: a device run on it is
// recorded, and the recording replays on the same volume to the same force log.
TEST_F(DicomMetaImageCliTest, DeviceRunsAndReplaysTakeAVolumeAtItsFinestSpacing) {
  const std::string folder = writeSeries("ct", "1.2.826.0.1.3680043.2.1125.7", kSlices);
  const std::string mha = writeMha("ct.mha");
  const glm::dvec3 c = boxCentreMm();
  const auto at = [](const glm::dvec3& p) {
    return std::to_string(p.x) + "," + std::to_string(p.y) + "," + std::to_string(p.z);
  };
  test::writeBytes(path("push.csv"), "t,x,y,z,drill_on\n0," + at(c + glm::dvec3(0, 0, 15)) +
                                         ",1\n2," + at(c) + ",1\n");
  for (const auto& [volume, name] : {std::pair<std::string, std::string>{folder, "dicom"},
                                     std::pair<std::string, std::string>{mha, "mha"}}) {
    const CliRun drill = osteon("drill '" + volume + "' --device scripted:'" + path("push.csv") +
                                "' --record '" + path(name + ".csv") +
                                "' --levels 0 --json --out-dir '" + path(name + "_drill") + "'");
    ASSERT_EQ(drill.exitCode, 0) << name << ": " << drill.err;
    const nlohmann::json d = nlohmann::json::parse(drill.out);
    EXPECT_DOUBLE_EQ(d["voxel_size_mm"].get<double>(), kPixelMm) << name;
    EXPECT_GT(d["removed_volume_mm3"].get<double>(), 1.0) << name;
    const CliRun replay = osteon("replay '" + path(name + ".csv") + "' '" + volume +
                                 "' --levels 0 --json --out-dir '" + path(name + "_replay") + "'");
    ASSERT_EQ(replay.exitCode, 0) << name << ": " << replay.err;
    EXPECT_EQ(nlohmann::json::parse(replay.out)["mode"], "replay") << name;
    EXPECT_TRUE(test::readBytes(path(name + "_drill/forces.csv")) ==
                test::readBytes(path(name + "_replay/forces.csv")))
        << name;
  }
  // A mesh still needs one.
  expectBadInput("drill default --path '" + path("push.csv") + "' --out-dir '" + path("m") + "'",
                 "--voxel-size", "required");
}

// info describes a volume as the commands that open it read it: a DICOM folder lists its series
// unless one is named.
TEST_F(DicomMetaImageCliTest, InfoDescribesAVolumeAsItIsRead) {
  const std::string folder = writeSeries("ct", "1.2.826.0.1.3680043.2.1125.7", kSlices);
  const std::string mha = writeMha("ct.mha");
  for (const auto& [args, format] :
       {std::pair<std::string, std::string>{"'" + mha + "'", "metaimage"},
        {"'" + folder + "' --series 1.2.826.0.1.3680043.2.1125.7", "dicom"}}) {
    const CliRun run = osteon("info " + args + " --json");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json j = nlohmann::json::parse(run.out);
    EXPECT_EQ(j["volume"]["format"], format);
    EXPECT_EQ(j["volume"]["kind"], "ct");
    EXPECT_DOUBLE_EQ(j["grid"]["voxel_size_mm"].get<double>(), kPixelMm);
    EXPECT_GT(j["voxels_inside"].get<std::uint64_t>(), 100u);
  }
  const nlohmann::json listed = nlohmann::json::parse(osteon("info '" + folder + "' --json").out);
  EXPECT_EQ(listed["series"].size(), 1u);
  expectBadInput("info '" + mha + "' --label 2", mha, "--label is for label maps");
}

TEST_F(DicomMetaImageCliTest, ValidateTakesBothAtTheirOwnVoxelSize) {
  ball_ = true;
  const std::string folder = writeSeries("ct", "1.2.826.0.1.3680043.2.1125.7", kSlices);
  const std::string mha = writeMha("ct.mha");
  const CliRun run = osteon("validate --quick --models '" + folder + "','" + mha + "' --out-dir '" +
                            path("v") + "'");
  ASSERT_EQ(run.exitCode, 0) << run.err << run.out;
  std::ifstream in(path("v/report.json"));
  const nlohmann::json report = nlohmann::json::parse(in);
  ASSERT_EQ(report["cases"].size(), 8u);  // 2 volumes x 1 voxel size x 2 methods x 2 modes
  for (const nlohmann::json& c : report["cases"]) {
    EXPECT_DOUBLE_EQ(c["voxel_size_mm"].get<double>(), kPixelMm);  // the finest spacing
    EXPECT_GT(c["triangles"].get<std::size_t>(), 0u);
  }
}

TEST_F(DicomMetaImageCliTest, SeriesAreListedAndPicked) {
  const std::string folder = writeSeries("two", "1.2.826.0.1.3680043.2.1125.7", kSlices);
  writeSeries("two", "1.2.826.0.1.3680043.2.1125.8", 3, 6);  // a short series beside it
  const CliRun info = osteon("info '" + folder + "'");
  ASSERT_EQ(info.exitCode, 0) << info.err;
  EXPECT_NE(info.out.find("2 series"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("1.2.826.0.1.3680043.2.1125.7: 16 slices (read by default)"),
            std::string::npos)
      << info.out;
  EXPECT_NE(info.out.find("1.2.826.0.1.3680043.2.1125.8: 3 slices"), std::string::npos);
  expectMeshedInPlace(folder, "dicom");
  // Named, the short series is read: three slices through the box.
  const CliRun three = osteon("mesh '" + folder + "' --series 1.2.826.0.1.3680043.2.1125.8 --json");
  ASSERT_EQ(three.exitCode, 0) << three.err;
  EXPECT_GT(nlohmann::json::parse(three.out)["triangles"].get<long long>(), 0);
  // The series read is named, in the JSON and in the text.
  EXPECT_EQ(nlohmann::json::parse(three.out)["volume"]["series_uid"],
            "1.2.826.0.1.3680043.2.1125.8");
  const CliRun text = osteon("mesh '" + folder + "' --out '" + path("t.ply") + "'");
  EXPECT_NE(
      text.out.find("volume      dicom uint16 series 1.2.826.0.1.3680043.2.1125.7, read as ct"),
      std::string::npos)
      << text.out;
  expectBadInput("mesh '" + folder + "' --series 9.9 --out '" + path("s.ply") + "'", folder,
                 "--series 9.9 is not among its series: 1.2.826.0.1.3680043.2.1125.7 (16 slices)");
  expectBadInput("mesh '" + path("ct.mha") + "' --series 9.9 --out '" + path("s.ply") + "'",
                 "--series 9.9", "only for DICOM");
}

}  // namespace
}  // namespace osteon
