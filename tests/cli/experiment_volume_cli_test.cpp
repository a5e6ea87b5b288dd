// `osteon experiment seed --mesh VOLUME`: a volume's surface, extracted at its own voxels, runs the
// seed's fourteen cases as a mesh does; volume options are refused for a mesh.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_fixture.h"

namespace osteon {
namespace {

TEST_F(CliTest, TheSeedExperimentRunsOnAVolumesSurface) {
  const CliRun grid =
      osteon("voxelize default --voxel-size 0.6 --out " + path("humerus.nrrd") + " --json");
  ASSERT_EQ(grid.exitCode, 0) << grid.err;
  const CliRun run = osteon("experiment seed --mesh " + path("humerus.nrrd") + " --out-dir " +
                            path("exp") + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["mesh"].get<std::string>(), path("humerus.nrrd"));
  ASSERT_EQ(j["runs"].size(), 14u);
  for (const nlohmann::json& r : j["runs"]) {
    // Every case drills into the head as it does on the mesh: bone removed, force near N_max.
    EXPECT_GT(r["removed_volume_mm3"].get<double>(), 50.0) << r.dump();
    EXPECT_GT(r["max_force_n"].get<double>(), 2.0) << r.dump();
    EXPECT_LE(r["max_force_n"].get<double>(), 3.3 + 1e-9) << r.dump();
  }
  EXPECT_EQ(j["plots"].size(), 6u);
}

TEST_F(CliTest, TheSeedExperimentRefusesVolumeOptionsForAMesh) {
  expectBadInput("experiment seed --label 1 --out-dir " + path("exp"), "--label",
                 "only for a volume");
}

}  // namespace
}  // namespace osteon
