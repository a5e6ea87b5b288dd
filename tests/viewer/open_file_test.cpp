// Opening files from the window (viewer/src/options.h): a mesh file's unit is asked for that
// file and nothing of the previous file's unit, scale, label or iso carries over to the next.
#include <gtest/gtest.h>

#include "options.h"

namespace osteon::viewer {
namespace {

TEST(OpenFileTest, OnlyMeshFilesAskForTheirUnit) {
  for (const char* mesh : {"a.stl", "b.OBJ", "dir/c.ply", "d.off"})
    EXPECT_TRUE(fileNeedsUnits(mesh)) << mesh;
  for (const char* other : {"default", "g.nrrd", "h.nhdr", "ct.nii.gz", "l.nii", "anchor-5"})
    EXPECT_FALSE(fileNeedsUnits(other)) << other;
}

TEST(OpenFileTest, ADroppedFileNeverInheritsThePreviousFilesUnit) {
  LoadRequest current;
  current.bone.input = "first.stl";
  current.bone.scale = 1000.0;  // the first file was in metres
  current.bone.units = "m";
  current.bone.volume.label = 3;
  current.bone.volume.isoValue = 250.0;
  current.levels = 1;
  current.tool = simulation::ToolKind::Burr;
  current.path = "portal-5";

  const LoadRequest mm = requestForFile(current, "second.stl", 1.0, 0.8);
  EXPECT_EQ(mm.bone.input, "second.stl");
  EXPECT_EQ(mm.bone.scaleToMm(), 1.0);
  EXPECT_EQ(mm.bone.defaultVoxelSizeMm, 0.8);
  EXPECT_FALSE(mm.bone.volume.label);
  EXPECT_FALSE(mm.bone.volume.isoValue);
  // The session's own choices stay; the path does not (another bone is drilled by hand).
  EXPECT_EQ(mm.levels, 1);
  EXPECT_EQ(mm.tool, simulation::ToolKind::Burr);
  EXPECT_TRUE(mm.path.empty());

  // An exercise names its own bone: nothing of the file's is set.
  const LoadRequest exercise = requestForFile(current, "anchor-7", std::nullopt, 1.2);
  EXPECT_EQ(exercise.exercise, "anchor-7");
  EXPECT_TRUE(isExercise("my-task.JSON"));
  EXPECT_FALSE(exercise.bone.scale);

  // A volume asked no unit: it gets none of the previous file's.
  const LoadRequest volume = requestForFile(current, "third.nrrd", std::nullopt, 1.2);
  EXPECT_FALSE(volume.bone.scale);
  EXPECT_EQ(volume.bone.scaleToMm(), 1.0);
}

}  // namespace
}  // namespace osteon::viewer
