#include "osteon/geometry/io/units.h"

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/shapes.h"

namespace osteon::geometry {
namespace {

TEST(Units, AdviceOnlyForBonesUnderAMillimetreOrOverTwoMetres) {
  EXPECT_EQ(unitsAdvice(361.0), "");
  EXPECT_EQ(unitsAdvice(1.0), "");
  EXPECT_EQ(unitsAdvice(2000.0), "");
  // A humerus saved in metres and read as millimetres.
  EXPECT_NE(unitsAdvice(0.361).find("metres read as millimetres: try " + optionRef("units") + " m"),
            std::string::npos);
  // Millimetres read with --units m.
  EXPECT_NE(unitsAdvice(361000.0, 1000.0)
                .find("millimetres read as metres: try " + optionRef("units") + " mm"),
            std::string::npos);
  // Centimetres read as millimetres are 36 mm: plausible, so no advice.
  EXPECT_EQ(unitsAdvice(36.1), "");
  // Nothing fits a bone: no advice rather than a wrong one.
  EXPECT_EQ(unitsAdvice(1e-9), "");
}

TEST(Units, VoxelizeNamesTheMeshExtentAndUnitsWhenNothingFits) {
  TriangleMesh metres = test::makeBox({0, 0, 0}, {0.05, 0.05, 0.36});
  VoxelizeOptions options;
  options.voxelSizeMm = 1.2;
  options.meshName = "humerus.stl";
  try {
    voxelize(metres, options);
    FAIL() << "a voxel larger than the mesh was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("humerus.stl: a 0.05 x 0.05 x 0.36 mm mesh at voxelSizeMm 1.2 mm"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("try units m"), std::string::npos) << what;
  }
  // A voxel that fits but a flat mesh with no inside: refused only when asked.
  const TriangleMesh flat = {{{0, 0, 0}, {10, 0, 0}, {0, 10, 0}}, {{0, 1, 2}}};
  options.voxelSizeMm = 1.0;
  options.meshName = "flat.stl";
  EXPECT_NO_THROW(voxelize(flat, options));
  options.requireInside = true;
  EXPECT_THROW(voxelize(flat, options), InputError);
  EXPECT_NO_THROW(voxelize(test::makeBox({0, 0, 0}, {10, 10, 10}), options));
}

}  // namespace
}  // namespace osteon::geometry
