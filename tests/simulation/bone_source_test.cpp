// BoneModel::open(BoneSource): every check of a source made once, its messages naming the
// BoneSource field (front ends name the flag), and what the input was read as.
#include "osteon/simulation/bone_source.h"

#include <string>

#include <gtest/gtest.h>

#include "osteon/core/option_error.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon::simulation {
namespace {

// The OptionError a source's opening throws, or a failure when it throws none (or another).
OptionError refusal(const BoneSource& source) {
  try {
    BoneModel::open(source);
  } catch (const OptionError& e) {
    return e;
  }
  ADD_FAILURE() << source.input << ": no OptionError";
  return OptionError("", "", "");
}

TEST(BoneSource, EachRefusalNamesItsFieldAndTheFrontEndsFlag) {
  BoneSource source;
  source.voxelSizeMm = 1.2;
  source.scale = 0.0;
  OptionError e = refusal(source);
  EXPECT_EQ(e.field(), "scale");
  EXPECT_STREQ(e.what(), "scale 0: must be a positive finite number");
  EXPECT_EQ(commandLineMessage(e), "--scale 0: must be a positive finite number");

  source.scale.reset();
  source.units = "furlong";
  EXPECT_EQ(refusal(source).field(), "units");

  source.units = "mm";
  source.voxelSizeMm = -1.0;
  e = refusal(source);
  EXPECT_STREQ(e.what(), "voxelSizeMm -1: must be a positive number of mm");
  EXPECT_EQ(commandLineMessage(e), "--voxel-size -1: must be a positive number of mm");

  source.voxelSizeMm.reset();
  e = refusal(source);
  EXPECT_EQ(commandLineMessage(e), "--voxel-size: required when the input is a mesh");

  source.voxelSizeMm = 1.2;
  source.volume.isoValue = 300.0;
  e = refusal(source);
  EXPECT_EQ(commandLineMessage(e),
            "--iso: only for a volume (.nrrd, .nhdr, .nii, .nii.gz, .mha, .mhd, DICOM); default is "
            "a mesh");
}

TEST(BoneSource, AMeshIsReadScaledAndVoxelizedAsNamed) {
  const std::string dir = test::makeTempDir("bone_source_mesh");
  geometry::writeMesh(test::makeSphere(0.01, 32, 16),
                      dir + "/ball.stl");  // 20 mm across, in metres
  BoneSource source;
  source.input = dir + "/ball.stl";
  source.units = "m";
  source.defaultVoxelSizeMm = 1.0;  // no voxelSizeMm: the front end's default
  source.sampleFineFills = false;
  const OpenedBone opened = BoneModel::open(source);
  EXPECT_EQ(opened.read.kind, "mesh");
  EXPECT_EQ(opened.read.scaleToMm, 1000.0);
  EXPECT_FALSE(opened.read.volume);
  EXPECT_EQ(opened.bone->name(), source.input);
  EXPECT_DOUBLE_EQ(opened.bone->grid().voxelSizeMm(), 1.0);
  EXPECT_NEAR(opened.bone->grid().filledVolumeMm3(), 4.0 / 3.0 * 3.14159265 * 1000.0, 150.0);
  EXPECT_EQ(source.inputFiles(), std::vector<std::string>{source.input});
}

TEST(BoneSource, AVolumeKeepsItsOwnVoxelSizeToOneTolerance) {
  const std::string dir = test::makeTempDir("bone_source_volume");
  geometry::VoxelizeOptions vo;
  vo.voxelSizeMm = 1.5;
  geometry::writeNrrd(geometry::voxelize(test::makeSphere(8.0, 32, 16), vo), dir + "/g.nrrd");
  BoneSource source;
  source.input = dir + "/g.nrrd";
  EXPECT_EQ(source.inputFiles(), (std::vector<std::string>{source.input, dir + "/g.density.nrrd"}));
  const OpenedBone own = BoneModel::open(source);  // no voxel size: the volume's
  EXPECT_EQ(own.read.kind, "osteon grid");
  ASSERT_TRUE(own.read.volume);
  EXPECT_DOUBLE_EQ(own.bone->grid().voxelSizeMm(), 1.5);
  source.voxelSizeMm = 1.5 * (1.0 + 1e-7);  // within rounding of the volume's
  EXPECT_NO_THROW(BoneModel::open(source));
  source.voxelSizeMm = 1.2;
  EXPECT_EQ(refusal(source).field(), "voxelSizeMm");
  source.voxelSizeMm.reset();
  source.volume.label = 1;  // meaningful for a volume: not refused as for a mesh
  EXPECT_NO_THROW(source.check());
}

TEST(BoneSource, ABoneForASessionMustHoldBoneAReadOneMayBeEmpty) {
  const std::string dir = test::makeTempDir("bone_source_empty");
  geometry::writeNrrd(geometry::VoxelGrid(glm::ivec3(8), glm::dvec3(0.0), 1.0),
                      dir + "/empty.nrrd");
  BoneSource source;
  source.input = dir + "/empty.nrrd";
  try {
    BoneModel::open(source);
    ADD_FAILURE() << "an empty grid opened for a session";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              source.input + ": the grid has no voxel inside (nothing to drill)");
  }
  source.forSession = false;
  const OpenedBone read = BoneModel::open(source);
  EXPECT_EQ(read.bone->grid().countVoxels(geometry::kFillHalf), 0u);
}

}  // namespace
}  // namespace osteon::simulation
