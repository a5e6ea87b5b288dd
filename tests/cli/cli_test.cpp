// The command line as users and scripts meet it: exit codes, one-line errors naming the file
// or value, JSON on stdout.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <string>
#include <sys/wait.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "osteon/geometry/io/mesh_io.h"
#include "support/cli_fixture.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon {
namespace {

std::string binaryStlHeader(std::uint32_t count) {
  std::string bytes(80, '\0');
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  return bytes;
}

// Set-up reported: setup_ms has every stage, none negative, the total at least its
// largest part but the surface (extracted beside the first steps, it is no part of the wait
// before them), the stages the command does not run 0; the surface there no earlier than it
// took; peak_rss_mb is positive. No timed assertions: the machine may be busy.
void expectSetupReported(const nlohmann::json& j, std::initializer_list<const char*> notRun) {
  ASSERT_TRUE(j.contains("setup_ms")) << j.dump();
  const nlohmann::json& setup = j["setup_ms"];
  double largest = 0.0;
  for (const char* key :
       {"load", "voxelize", "density", "fine_fills", "hierarchy", "surface", "total"}) {
    ASSERT_TRUE(setup.contains(key)) << key;
    EXPECT_GE(setup[key].get<double>(), 0.0) << key;
    if (std::string(key) != "total" && std::string(key) != "surface")
      largest = std::max(largest, setup[key].get<double>());
  }
  EXPECT_GE(setup["total"].get<double>(), largest);
  if (setup.contains("surface_ready") && setup["surface"].get<double>() > 0.0) {
    EXPECT_GE(setup["surface_ready"].get<double>(), setup["surface"].get<double>());
  }
  for (const char* key : notRun) EXPECT_EQ(setup[key].get<double>(), 0.0) << key;
  ASSERT_TRUE(j.contains("peak_rss_mb"));
  EXPECT_GT(j["peak_rss_mb"].get<double>(), 0.0);
}

// What a drilling session held, by structure (drill's `memory`): every part counted in the
// total, per voxel with bone alike; the visual side's grid only after a threaded run.
void expectMemoryReported(const nlohmann::json& j, bool threaded) {
  const nlohmann::json& memory = j["memory"];
  EXPECT_EQ(memory["voxels"], j["voxels"]);
  double parts = 0.0;
  for (const char* key : {"bone_grid", "fine_fills", "grid", "hierarchy", "refinement", "thermal",
                          "visual_grid", "surface"}) {
    ASSERT_TRUE(memory["bytes"].contains(key)) << key;
    parts += memory["bytes"][key].get<double>();
    EXPECT_NEAR(memory["bytes_per_voxel"][key].get<double>() * j["voxels"].get<double>(),
                memory["bytes"][key].get<double>(), 1.0)
        << key;
  }
  EXPECT_EQ(parts, memory["bytes"]["total"].get<double>());
  for (const char* key : {"bone_grid", "grid", "hierarchy", "surface", "surface_vertices"})
    EXPECT_GT(memory["bytes"][key].get<double>(), 0.0) << key;
  EXPECT_EQ(memory["bytes"]["visual_grid"].get<double>() > 0.0, threaded);
}

TEST_F(CliTest, EveryBadMeshGivesItsErrorAndExitCode2) {
  const std::string tri(50, '\0');
  test::writeBytes(path("truncated.stl"), binaryStlHeader(4) + tri);
  test::writeBytes(path("overflow.stl"), binaryStlHeader(0xF0000000u) + tri);
  test::writeBytes(path("empty.obj"), "# nothing here\n");
  test::writeBytes(path("noface.off"), "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  test::writeBytes(path("nan.obj"), "v 0 0 0\nv 0 NaN 0\nv 0 1 0\nf 1 2 3\n");
  test::writeBytes(path("inf.ply"),
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                   "end_header\n0 0 0\n1 0 -inf\n0 1 0\n3 0 1 2\n");
  test::writeBytes(path("range.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n");
  test::writeBytes(path("mesh.3ds"), "whatever");
  const struct {
    const char* file;
    const char* reason;
  } cases[] = {{"missing.stl", "no such file"},
               {"mesh.3ds", "unknown mesh extension"},
               {"truncated.stl", "truncated binary STL"},
               {"overflow.stl", "overflows 32-bit"},
               {"empty.obj", "empty mesh"},
               {"noface.off", "zero triangles"},
               {"nan.obj", "non-finite"},
               {"inf.ply", "non-finite"},
               {"range.obj", "out of range"}};
  for (const auto& c : cases) {
    expectBadInput("info '" + path(c.file) + "'", path(c.file), c.reason);
    expectBadInput("voxelize '" + path(c.file) + "' --voxel-size 1 --json", path(c.file), c.reason);
  }
}

TEST_F(CliTest, BadValuesAndUsageGiveExitCode2) {
  expectBadInput("voxelize default --voxel-size 0", "--voxel-size 0", "positive");
  expectBadInput("voxelize default --voxel-size -3", "--voxel-size -3", "positive");
  expectBadInput("voxelize default --voxel-size nan", "--voxel-size nan", "positive");
  expectBadInput("voxelize default --voxel-size 0.00001", "--voxel-size", "limit");
  expectBadInput("voxelize default --voxel-size abc", "abc", "");
  expectBadInput("voxelize default", "--voxel-size", "required");
  expectBadInput("info default --units furlong", "furlong", "unknown unit");
  expectBadInput("info default --units m --scale 2", "--units", "excludes");
  expectBadInput("info default --scale 0", "--scale 0", "positive");
  expectBadInput("voxelize default --voxel-size 1 --rays 0", "--rays 0", "1..16");
  expectBadInput("voxelize default --voxel-size 1 --cortical-density 0", "--cortical-density",
                 "1..32767");
  expectBadInput("frobnicate", "frobnicate", "");
  expectBadInput("", "subcommand", "");
  expectBadInput("voxelize default --voxel-size 1 --out '" + path("no/such/dir/g.nrrd") + "'",
                 path("no/such/dir/g.nrrd"), "");
}

TEST_F(CliTest, HelpAndVersionSucceed) {
  EXPECT_EQ(osteon("--help").exitCode, 0);
  EXPECT_EQ(osteon("voxelize --help").exitCode, 0);
  const CliRun version = osteon("--version");
  EXPECT_EQ(version.exitCode, 0);
  EXPECT_NE(version.out.find("osteon"), std::string::npos);
}

TEST_F(CliTest, VoxelizeDefaultPrintsTheContractJson) {
  const CliRun run =
      osteon("voxelize default --voxel-size 1.2 --json --out '" + path("g.nrrd") + "'");
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  for (const char* key : {"dims", "voxel_size_mm", "voxels_inside", "bricks_allocated",
                          "volume_mm3", "mesh_volume_mm3", "time_ms"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["dims"].size(), 3u);
  EXPECT_DOUBLE_EQ(j["voxel_size_mm"].get<double>(), 1.2);
  EXPECT_GT(j["voxels_inside"].get<long long>(), 1000);
  const double volume = j["volume_mm3"].get<double>();
  const double meshVolume = j["mesh_volume_mm3"].get<double>();
  EXPECT_NEAR(volume, meshVolume, 0.01 * meshVolume);
  expectSetupReported(j, {"fine_fills", "hierarchy", "surface"});
  EXPECT_TRUE(std::filesystem::exists(path("g.nrrd")));
  EXPECT_TRUE(std::filesystem::exists(path("g.density.nrrd")));
}

TEST_F(CliTest, UnitsAndScaleAgree) {
  geometry::writeMesh(test::makeBox({0, 0, 0}, {0.02, 0.03, 0.04}), path("box_m.stl"));
  const CliRun metres = osteon("info '" + path("box_m.stl") + "' --units m --json");
  const CliRun scaled = osteon("info '" + path("box_m.stl") + "' --scale 1000 --json");
  ASSERT_EQ(metres.exitCode, 0) << metres.err;
  ASSERT_EQ(scaled.exitCode, 0) << scaled.err;
  const double v1 = nlohmann::json::parse(metres.out)["volume_mm3"].get<double>();
  const double v2 = nlohmann::json::parse(scaled.out)["volume_mm3"].get<double>();
  EXPECT_NEAR(v1, 20.0 * 30.0 * 40.0, 0.1);
  EXPECT_DOUBLE_EQ(v1, v2);
  const CliRun inches = osteon("info '" + path("box_m.stl") + "' --units in --json");
  EXPECT_NEAR(nlohmann::json::parse(inches.out)["volume_mm3"].get<double>(),
              0.02 * 0.03 * 0.04 * 25.4 * 25.4 * 25.4, 1e-6);
}

TEST_F(CliTest, HierarchyReportsLevelsForMeshesAndGrids) {
  const CliRun mesh =
      osteon("hierarchy default --voxel-size 1.2 --json --svg '" + path("h.svg") + "'");
  ASSERT_EQ(mesh.exitCode, 0) << mesh.err;
  const nlohmann::json j = nlohmann::json::parse(mesh.out);
  for (const char* key : {"levels", "nodes_per_level", "build_ms", "memory_bytes", "voxels"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_TRUE(j["valid"].get<bool>());
  expectSetupReported(j, {"fine_fills", "surface"});
  const auto& levels = j["nodes_per_level"];
  ASSERT_EQ(levels.size(), j["levels"].get<std::size_t>());
  EXPECT_EQ(levels.back()["nodes"].get<int>(), 1);  // one root
  EXPECT_EQ(levels[0]["nodes"].get<long long>(), j["voxels"].get<long long>());
  long long cell = 1;
  for (const auto& level : levels) {
    EXPECT_EQ(level["cell_voxels"].get<long long>(), cell);  // xi^L
    cell *= 3;
  }
  EXPECT_NE(test::readBytes(path("h.svg")).find("<svg"), std::string::npos);

  // The same grid through NRRD gives the same hierarchy.
  ASSERT_EQ(osteon("voxelize default --voxel-size 1.2 --out '" + path("g.nrrd") + "'").exitCode, 0);
  const CliRun grid = osteon("hierarchy '" + path("g.nrrd") + "' --json");
  ASSERT_EQ(grid.exitCode, 0) << grid.err;
  EXPECT_EQ(nlohmann::json::parse(grid.out)["nodes_per_level"], levels);
  expectSetupReported(nlohmann::json::parse(grid.out),
                      {"voxelize", "density", "fine_fills", "surface"});

  expectBadInput("hierarchy default", "--voxel-size", "required");
  expectBadInput("hierarchy default --voxel-size 1.2 --xi 4", "--xi 4", "odd");
  expectBadInput("hierarchy '" + path("g.nrrd") + "' --voxel-size 0.5", "--voxel-size 0.5",
                 "1.2 mm");
  expectBadInput("hierarchy default --voxel-size 1.2 --slice-z 900", "--slice-z 900", "outside");
}

TEST_F(CliTest, MeshIsClosedForCrackFreeAndCrackedForNaive) {
  const CliRun good = osteon("mesh default --voxel-size 1.2 --json --out '" + path("s.ply") + "'");
  ASSERT_EQ(good.exitCode, 0) << good.err;
  const nlohmann::json j = nlohmann::json::parse(good.out);
  EXPECT_EQ(j["border_edges"].get<int>(), 0);
  EXPECT_EQ(j["non_manifold_edges"].get<int>(), 0);
  EXPECT_EQ(j["euler_characteristic"].get<int>(), 2);
  EXPECT_GT(j["triangles"].get<int>(), 10000);
  for (const char* key : {"total", "extract", "smooth", "normals", "other"}) {
    EXPECT_TRUE(j["time_ms"].contains(key)) << key;
  }
  expectSetupReported(j, {"fine_fills", "hierarchy"});
  EXPECT_EQ(geometry::readMesh(path("s.ply")).triangleCount(), j["triangles"].get<std::size_t>());
  const CliRun naive = osteon("mesh default --voxel-size 1.2 --method naive --json");
  ASSERT_EQ(naive.exitCode, 0) << naive.err;
  EXPECT_GT(nlohmann::json::parse(naive.out)["border_edges"].get<int>(), 0);
  expectBadInput("mesh default --voxel-size 1.2 --method marching", "--method marching", "unknown");
  expectBadInput("mesh default --voxel-size 1.2 --smooth -1", "--smooth -1", "0..100");
  expectBadInput("mesh default --voxel-size 1.2 --out '" + path("s.vtk") + "'", path("s.vtk"),
                 "unknown mesh extension");
}

TEST_F(CliTest, DrillWritesTheLogSummaryAndSurfaceAndIsDeterministic) {
  const std::string args =
      "drill default --voxel-size 1.2 --levels 1 --path portal-7 --json --out-dir ";
  const CliRun run = osteon(args + "'" + path("a") + "'");
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  for (const char* key : {"jitter_n", "max_step_change_n", "max_force_n", "removed_volume_mm3",
                          "haptic_step_us", "remesh_ms", "overruns", "steps"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  for (const char* key : {"p50", "p99", "max"}) {
    EXPECT_TRUE(j["haptic_step_us"].contains(key)) << key;
    EXPECT_TRUE(j["remesh_ms"].contains(key)) << key;
  }
  EXPECT_EQ(j["steps"].get<int>(), 7001);
  // Nothing ran out of room: every cut, refinement and removal mask fitted.
  for (const char* key :
       {"cut_overflows", "refine_pool_exhausted", "mask_overflows", "brick_allocations"}) {
    ASSERT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j[key].get<int>(), 0) << key;
  }
  EXPECT_GT(j["removed_volume_mm3"].get<double>(), 10.0);
  EXPECT_LE(j["max_force_n"].get<double>(), 3.3);
  // Set-up from the file to the first step, the path's head fit and plan included.
  expectSetupReported(j, {});
  EXPECT_GT(j["setup_ms"]["first_step"].get<double>(), 0.0);
  EXPECT_GE(j["setup_ms"]["path"].get<double>(), 0.0);
  expectMemoryReported(j, false);
  EXPECT_GE(j["setup_ms"]["total"].get<double>(), j["setup_ms"]["path"].get<double>());
  EXPECT_GT(j["setup_peak_rss_mb"].get<double>(), 0.0);
  EXPECT_GE(j["peak_rss_mb"].get<double>(), j["setup_peak_rss_mb"].get<double>());
  EXPECT_TRUE(nlohmann::json::parse(test::readBytes(path("a/summary.json"))).contains("setup_ms"));
  EXPECT_EQ(nlohmann::json::parse(test::readBytes(path("a/summary.json")))["steps"], j["steps"]);
  const std::string log = test::readBytes(path("a/forces.csv"));
  EXPECT_EQ(log.substr(0, log.find('\n')),
            "t,px,py,pz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level");
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 7002);
  // The drilled surface is closed.
  const geometry::TriangleMesh surface = geometry::readMesh(path("a/surface.ply"));
  EXPECT_EQ(geometry::analyzeTopology(surface).borderEdges, 0u);
  // The same input gives the same log, byte for byte.
  ASSERT_EQ(osteon(args + "'" + path("b") + "'").exitCode, 0);
  EXPECT_TRUE(log == test::readBytes(path("b/forces.csv")));

  // The same run on the three real-time threads.
  const CliRun threaded = osteon(
      "drill default --voxel-size 1.2 --levels 0 --path portal-5 --threaded --json --out-dir '" +
      path("t") + "'");
  ASSERT_EQ(threaded.exitCode, 0) << threaded.err;
  const nlohmann::json t = nlohmann::json::parse(threaded.out);
  EXPECT_EQ(t["mode"], "threaded");
  // Levels 0; the visual thread extracts its own surface beside the first steps.
  expectSetupReported(t, {"fine_fills"});
  EXPECT_GT(t["setup_ms"]["first_step"].get<double>(), 0.0);
  EXPECT_GT(t["setup_ms"]["surface_ready"].get<double>(), 0.0);
  expectMemoryReported(t, true);
  EXPECT_GT(t["runtime"]["collision_steps"].get<int>(),
            3500);  // most periods, even on a busy machine
  EXPECT_GT(t["runtime"]["visual_updates"].get<int>(), 0);
  EXPECT_EQ(t["runtime"]["ring_full"].get<int>(), 0);
  EXPECT_LE(t["runtime"]["haptic_standby_steps"].get<int>(),
            t["runtime"]["haptic_steps"].get<int>());
  EXPECT_GT(t["removed_volume_mm3"].get<double>(), 10.0);

  test::writeBytes(path("p.csv"), "t,x,y,z,drill_on\n0,0,0,80,1\n1,0,0,60,1\n");
  // In the air: a path that never meets bone is an empty result, accepted here on purpose.
  const CliRun csv =
      osteon("drill default --voxel-size 1.2 --levels 0 --tool burr --json --allow-empty --path '" +
             path("p.csv") + "' --out-dir '" + path("c") + "'");
  ASSERT_EQ(csv.exitCode, 0) << csv.err;
  EXPECT_EQ(nlohmann::json::parse(csv.out)["steps"].get<int>(), 1001);
  EXPECT_EQ(nlohmann::json::parse(csv.out)["max_force_n"].get<double>(), 0.0);  // in the air
  EXPECT_TRUE(nlohmann::json::parse(csv.out)["empty"].get<bool>());

  expectBadInput("drill default --voxel-size 1.2 --levels 3 --path portal-5", "--levels 3",
                 "0, 1 or 2");
  expectBadInput("drill default --voxel-size 1.2 --path portal-6", "portal-6", "not a portal");
  expectBadInput("drill default --voxel-size 1.2 --path portal-5 --tool scalpel", "scalpel",
                 "unknown tool");
  expectBadInput("drill default --voxel-size 0 --path portal-5", "--voxel-size 0", "positive");
  test::writeBytes(path("bad.csv"), "t,x,y,z,drill_on\n0,0,0,0,1\n0.5,0,nan?,0,1\n");
  expectBadInput("drill default --voxel-size 1.2 --path '" + path("bad.csv") + "'", "bad.csv:3",
                 "not a finite number");
  expectBadInput("drill default --voxel-size 1.2 --path '" + path("none.csv") + "'", "none.csv",
                 "cannot open");
}

// Seed section 4: 14 runs, six plots, and the dynamic runs smoother than the static ones.
TEST_F(CliTest, ExperimentSeedDrawsThePlotsAndTheJitterTable) {
  const CliRun run = osteon("experiment seed --json --out-dir '" + path("exp") + "'");
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  ASSERT_EQ(j["runs"].size(), 14u);
  ASSERT_EQ(j["plots"].size(), 6u);
  for (const auto& image : j["plots"]) {
    const std::string bytes = test::readBytes(path("exp/" + image.get<std::string>()));
    ASSERT_GT(bytes.size(), 10000u) << image;
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << image;
  }
  std::map<std::string, double> staticJitter;
  for (const auto& r : j["runs"]) {
    const std::string key =
        std::to_string(r["voxel_size_mm"].get<double>()) + r["portal"].get<std::string>();
    if (r["levels"].get<int>() == 0) {
      staticJitter[key] = r["jitter_n"].get<double>();
    } else {
      EXPECT_LT(r["jitter_n"].get<double>(), staticJitter.at(key)) << r.dump();
    }
  }
  EXPECT_NE(test::readBytes(path("exp/jitter.md")).find("| 1.2 mm | portal-7 | 2 |"),
            std::string::npos);
  // The 14 force logs, byte for byte (64-bit FNV-1a of each forces.csv), as they were before
  // the faster set-up (lattice and grid DPH builds, parallel first surface): changes to how
  // a bone is built or walked must not move a single force.
  const std::pair<const char*, std::uint64_t> logs[] = {
      {"0.72mm_portal-5_L0", 0xc3acfb5a4876f0a6ull}, {"0.72mm_portal-5_L1", 0x337c883488a74dbaull},
      {"0.72mm_portal-7_L0", 0xa8e5caa1fbecea89ull}, {"0.72mm_portal-7_L1", 0x5578f96db885874cull},
      {"0.9mm_portal-5_L0", 0xa3f4746e28ed37dcull},  {"0.9mm_portal-5_L1", 0xe5a977f7276f0a5bull},
      {"0.9mm_portal-7_L0", 0x5cfea41ed3d60549ull},  {"0.9mm_portal-7_L1", 0x23c9110f77fdca29ull},
      {"1.2mm_portal-5_L0", 0xc6bc836733d2f5c8ull},  {"1.2mm_portal-5_L1", 0x794349eb6f6702e6ull},
      {"1.2mm_portal-5_L2", 0x4772912d6698b2c3ull},  {"1.2mm_portal-7_L0", 0x3efd8aac745f2651ull},
      {"1.2mm_portal-7_L1", 0x91cc7d3eec27b1baull},  {"1.2mm_portal-7_L2", 0xc876661ed38dd7ffull}};
  for (const auto& [runName, expected] : logs) {
    const std::string bytes =
        test::readBytes(path("exp/runs/" + std::string(runName) + "/forces.csv"));
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const char c : bytes)
      h = (h ^ std::uint64_t(static_cast<unsigned char>(c))) * 0x100000001b3ull;
    EXPECT_EQ(h, expected) << runName << ": forces.csv is not the byte-identical log ("
                           << bytes.size() << " bytes)";
  }
  expectBadInput("experiment lunar", "experiment lunar", "unknown");
}

TEST_F(CliTest, CheckPassesTheCrackFreeSurfaceAndFailsTheNaiveOne) {
  ASSERT_EQ(osteon("mesh default --voxel-size 1.2 --out '" + path("cf.ply") + "'").exitCode, 0);
  ASSERT_EQ(osteon("mesh default --voxel-size 1.2 --method naive --out '" + path("naive.ply") + "'")
                .exitCode,
            0);
  const CliRun good =
      osteon("check '" + path("cf.ply") + "' --reference default --cracks 128 --json --images '" +
             path("img") + "'");
  ASSERT_EQ(good.exitCode, 0) << good.err;
  const nlohmann::json g = nlohmann::json::parse(good.out);
  EXPECT_EQ(g["verdict"], "PASS");
  EXPECT_EQ(g["border_edges"].get<int>(), 0);
  EXPECT_EQ(g["self_intersections"].get<int>(), 0);
  EXPECT_TRUE(g["outward_oriented"].get<bool>());
  EXPECT_EQ(g["genus"].get<int>(), 0);
  EXPECT_EQ(g["crack_percent"].get<double>(), 0.0);
  EXPECT_LT(g["hausdorff_mm"].get<double>(), 1.2);  // within a voxel of the model
  EXPECT_EQ(g["crack_images"].size(), 6u);
  EXPECT_EQ(test::readBytes(path("img/cracks_+x.png")).substr(1, 3), "PNG");
  const CliRun bad = osteon("check '" + path("naive.ply") + "' --cracks 128 --json");
  EXPECT_EQ(bad.exitCode, 1) << bad.err;
  const nlohmann::json b = nlohmann::json::parse(bad.out);
  EXPECT_EQ(b["verdict"], "FAIL");
  EXPECT_GT(b["border_edges"].get<int>(), 0);
  EXPECT_GT(b["crack_percent"].get<double>(), 1.0);
  expectBadInput("check '" + path("cf.ply") + "' --cracks 4", "--cracks 4", "16..4096");
  expectBadInput("check '" + path("none.ply") + "'", "none.ply", "");
}

// The nightly run, quick: the crack-free method keeps every guarantee, the naive one breaks
// them (measured here, not assumed), and the report follows its schema.
TEST_F(CliTest, ValidateQuickPassesAndReportsTheNaiveCracks) {
  const CliRun run = osteon("validate --quick --out-dir '" + path("v") + "'");
  ASSERT_EQ(run.exitCode, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("[4/4]"), std::string::npos);  // progress per case
  const nlohmann::json j = nlohmann::json::parse(test::readBytes(path("v/report.json")));
  EXPECT_EQ(j["schema"], "osteon-validate/1");
  EXPECT_EQ(j["verdict"], "PASS");
  ASSERT_EQ(j["cases"].size(), 4u);
  for (const auto& c : j["cases"]) {
    for (const char* key :
         {"model", "voxel_size_mm", "method", "mode", "border_edges", "non_manifold",
          "self_intersections", "crack_percent", "hausdorff_mm", "collision_misses",
          "collision_rays", "collision_missed_samples", "collision_boundary_samples",
          "collision_skipped_samples", "collision_worst_miss_mm", "max_force_n", "jitter_n", "pass",
          "failures"}) {
      EXPECT_TRUE(c.contains(key)) << key;
    }
    EXPECT_LE(c["max_force_n"].get<double>(), 3.3);
    EXPECT_GT(c["max_force_n"].get<double>(), 1.0);  // the paths met bone
    if (c["method"] == "crackfree") {
      EXPECT_TRUE(c["pass"].get<bool>()) << c.dump();
      EXPECT_EQ(c["border_edges"].get<int>(), 0);
      EXPECT_EQ(c["crack_percent"].get<double>(), 0.0);
      EXPECT_EQ(c["collision_misses"].get<int>(), 0);
      EXPECT_GT(c["collision_checks"].get<int>(), 500);
      EXPECT_GT(c["collision_rays"].get<int>(), 5000);
      EXPECT_EQ(c["collision_missed_samples"].get<int>(), 0);
      EXPECT_EQ(c["after"]["border_edges"].get<int>(), 0);
    } else {
      EXPECT_FALSE(c["pass"].get<bool>());
      EXPECT_GT(c["border_edges"].get<int>(), 0);
      EXPECT_GT(c["crack_percent"].get<double>(), 0.0);
      EXPECT_GT(c["collision_misses"].get<int>(), 0) << c["mode"];  // rays through its cracks
    }
  }
  EXPECT_GT(j["cases"][0]["mesh_time_ms"]["total"].get<double>(), 0.0);
  EXPECT_GT(j["cases"][0]["voxels"].get<int>(), 10000);
  // What produced the numbers: the build, the machine and the libraries linked.
  const nlohmann::json& env = j["environment"];
  for (const char* key : {"compiler", "build_type", "os", "cpu"}) {
    ASSERT_TRUE(env.contains(key)) << key;
    EXPECT_FALSE(env[key].get<std::string>().empty()) << key;
  }
  for (const char* library : {"cgal", "embree", "openmesh", "tbb", "glm", "openimageio"}) {
    ASSERT_TRUE(env["libraries"].contains(library)) << library;
    EXPECT_NE(env["libraries"][library].get<std::string>().find('.'), std::string::npos) << library;
  }
  const std::string html = test::readBytes(path("v/report.html"));
  EXPECT_NE(html.find("osteon validation: <span class=\"pass\">PASS"), std::string::npos);
  EXPECT_NE(html.find("beside the seed's Tables 1 and 2"), std::string::npos);
  EXPECT_NE(html.find("openimageio"), std::string::npos);  // the environment block
  ASSERT_EQ(j["plots"].size(), 2u);                        // static against dynamic, one per portal
  for (const auto& plot : j["plots"]) {
    EXPECT_EQ(test::readBytes(path("v/" + plot.get<std::string>())).substr(1, 3), "PNG") << plot;
    EXPECT_NE(html.find(plot.get<std::string>()), std::string::npos);
  }
  EXPECT_NE(html.find("images/0_naive/cracks_+x.png"), std::string::npos);
  EXPECT_FALSE(test::readBytes(path("v/images/0_naive/cracks_+x.png")).empty());

  // --compare: an older report in which a crack-free case was smoother marks a regression.
  nlohmann::json older = j;
  older["cases"][0]["jitter_n"] = 0.5 * j["cases"][0]["jitter_n"].get<double>();
  test::writeBytes(path("old.json"), older.dump());
  const CliRun again =
      osteon("validate --quick --out-dir '" + path("w") + "' --compare '" + path("old.json") + "'");
  ASSERT_EQ(again.exitCode, 0) << again.err;
  const nlohmann::json k = nlohmann::json::parse(test::readBytes(path("w/report.json")));
  ASSERT_EQ(k["regressions"].size(), 1u);
  EXPECT_NE(k["regressions"][0]["what"].get<std::string>().find("jitter_n"), std::string::npos);

  expectBadInput("validate --voxel-sizes 1.2,abc", "--voxel-sizes 1.2,abc", "not a voxel size");
  expectBadInput("validate --quick --compare '" + path("none.json") + "'", "none.json",
                 "cannot open");
}

TEST_F(CliTest, ModelCommandRegeneratesTheShippedDefault) {
  const CliRun run = osteon("model --json --out '" + path("humerus.stl") + "'");
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_TRUE(j["closed"].get<bool>());
  EXPECT_NEAR(j["head_radius_mm"].get<double>(), 23.0, 1.0);
  // The file in data/ is what this command writes, byte for byte.
  const bool same = test::readBytes(path("humerus.stl")) ==
                    test::readBytes(std::string(OSTEON_SOURCE_DIR) + "/data/humerus_proximal.stl");
  EXPECT_TRUE(same)
      << "data/humerus_proximal.stl is stale: run `osteon model --out data/humerus_proximal.stl`";
}

}  // namespace
}  // namespace osteon
