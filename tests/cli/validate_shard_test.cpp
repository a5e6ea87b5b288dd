// The nightly run split over machines: `validate --shard K/N` runs disjoint parts of the cases,
// `validate --merge` joins their reports into the report the whole run writes, and refuses
// shards that do not make one run.
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "osteon/geometry/io/mesh_io.h"
#include "support/cli_fixture.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon {
namespace {

using nlohmann::json;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

// A report's cases without their wall times, which differ run to run.
json casesWithoutTimes(const json& report) {
  json cases = report.at("cases");
  for (json& c : cases) {
    for (const char* timing : {"extract_ms", "mesh_time_ms", "case_ms"}) {
      EXPECT_TRUE(c.contains(timing)) << timing;  // a renamed field would otherwise stay in
      c.erase(timing);
    }
  }
  return cases;
}

class ValidateShardTest : public CliTest {
 protected:
  json report(const std::string& dir) const {
    return json::parse(test::readBytes(path(dir + "/report.json")));
  }

  // A shard run that must succeed; its report.
  json shard(const std::string& run, std::size_t k, std::size_t n, const std::string& dir) const {
    const CliRun r = osteon("validate " + run + " --shard " + std::to_string(k) + "/" +
                            std::to_string(n) + " --out-dir " + quoted(path(dir)));
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
    return report(dir);
  }

  std::string mergeArgs(const std::vector<std::string>& dirs, const std::string& out) const {
    std::string args = "validate --merge";
    for (const std::string& d : dirs) args += " " + quoted(path(d));
    return args + " --out-dir " + quoted(path(out));
  }

  // A torus: checked but not drilled (no humeral head), so a run of it takes about a second.
  std::string torusRun(const std::string& sizes) const {
    geometry::writeMesh(test::makeTorus(20.0, 7.0, 48, 24), path("torus.stl"));
    return "--quick --models " + quoted(path("torus.stl")) + " --voxel-sizes " + sizes;
  }
};

// Merged shards give the whole run's report, case for case: a torus (not drilled) and the
// built-in bone (drilled) at two sizes are four case groups of different cost, split in 4 (one
// group each) and in 3 (the two cheapest together). One whole run, one of each split.
TEST_F(ValidateShardTest, MergedShardsEqualTheWholeRun) {
  geometry::writeMesh(test::makeTorus(20.0, 7.0, 48, 24), path("torus.stl"));
#ifdef OSTEON_SLOW_BUILD
  const std::string sizes = "3.0";    // two groups: sanitizers run the drilling 2-15x slower
  const std::string firstSize = "3";  // as a case key writes it
#else
  const std::string sizes = "2.4,3.0";
  const std::string firstSize = "2.4";
#endif
  // The torus first: the split (costliest first) then differs from the run's order, which the
  // merge must restore.
  const std::string run =
      "--quick --models " + quoted(path("torus.stl")) + ",default --voxel-sizes " + sizes;
  const CliRun whole = osteon("validate " + run + " --out-dir " + quoted(path("whole")));
  ASSERT_EQ(whole.exitCode, 0) << whole.out << whole.err;
  const json w = report("whole");
  EXPECT_FALSE(w.contains("shard"));
  const std::size_t groups = w["options"]["voxel_sizes_mm"].size() * 2;
  ASSERT_EQ(w["cases"].size(), 4 * groups);

  for (const std::size_t n : {std::size_t{4}, std::size_t{3}}) {
    SCOPED_TRACE(std::to_string(n) + " shards");
    std::vector<std::string> dirs;
    std::set<std::string> seen;
    std::size_t cases = 0;
    for (std::size_t k = 0; k < n; ++k) {
      dirs.push_back("s" + std::to_string(n) + "_" + std::to_string(k));
      const json s = shard(run, k, n, dirs.back());
      ASSERT_TRUE(s.contains("shard")) << s.dump();
      EXPECT_EQ(s["shard"]["index"], k);
      EXPECT_EQ(s["shard"]["count"], n);
      // The whole run's cases, by model|voxel mm|method|mode, in its order.
      ASSERT_EQ(s["shard"]["case_list"].size(), w["cases"].size());
      const std::size_t defaultFirst = 4 * groups / 2;  // after the torus's groups
      EXPECT_EQ(s["shard"]["case_list"][defaultFirst],
                "default|" + firstSize + "|crackfree|static");
      EXPECT_EQ(s["shard"]["case_list"][defaultFirst + 3],
                "default|" + firstSize + "|naive|dynamic");
      // Whole groups: a group's four cases share a voxelization.
      EXPECT_EQ(s["cases"].size() % 4, 0u);
      for (const json& key : s["shard"]["cases"])
        EXPECT_TRUE(seen.insert(key.get<std::string>()).second) << key;
      cases += s["cases"].size();
    }
    EXPECT_EQ(cases, w["cases"].size());  // disjoint (above) and together every case

    const std::string out = "merged" + std::to_string(n);
    const CliRun merge = osteon(mergeArgs(dirs, out));
    ASSERT_EQ(merge.exitCode, 0) << merge.out << merge.err;
    const json m = report(out);
    EXPECT_EQ(m["schema"], "osteon-validate/1");
    EXPECT_FALSE(m.contains("shard"));
    EXPECT_EQ(m["verdict"], w["verdict"]);
    EXPECT_EQ(m["options"], w["options"]);
    EXPECT_EQ(m["osteon_version"], w["osteon_version"]);
    EXPECT_EQ(casesWithoutTimes(m), casesWithoutTimes(w));
    ASSERT_EQ(m["merged_from"].size(), n);
    EXPECT_EQ(m["merged_from"][0], path(dirs[0]));
    // The images and plots of every shard, in the whole run's order, copied beside the report.
    EXPECT_EQ(m["images"], w["images"]);
    EXPECT_EQ(m["plots"], w["plots"]);
    const std::string html = test::readBytes(path(out + "/report.html"));
    EXPECT_NE(html.find("osteon validation: <span class=\"pass\">PASS"), std::string::npos);
    for (const char* list : {"images", "plots"}) {
      ASSERT_FALSE(m[list].empty()) << list;
      for (const json& file : m[list]) {
        EXPECT_EQ(test::readBytes(path(out + "/" + file.get<std::string>())).substr(1, 3), "PNG")
            << file;
        EXPECT_NE(html.find(file.get<std::string>()), std::string::npos) << file;
      }
    }
  }

  // --compare works on a merge as on a run: a smoother old crack-free case is a regression (of
  // the drilled bone: the torus has no forces).
  json older = w;
  const std::size_t drilled = 4 * groups / 2;
  ASSERT_EQ(w["cases"][drilled]["model"], "default");
  older["cases"][drilled]["jitter_n"] = 0.5 * w["cases"][drilled]["jitter_n"].get<double>();
  test::writeBytes(path("old.json"), older.dump());
  const CliRun compared = osteon(mergeArgs({"s3_0", "s3_1", "s3_2"}, "compared") + " --compare " +
                                 quoted(path("old.json")));
  ASSERT_EQ(compared.exitCode, 0) << compared.err;
  const json c = report("compared");
  ASSERT_EQ(c["regressions"].size(), 1u);
  EXPECT_NE(c["regressions"][0]["what"].get<std::string>().find("jitter_n"), std::string::npos);
}

// A shard with no case (more shards than case groups) still writes a report a merge takes; a
// merged failure exits as a run's does.
TEST_F(ValidateShardTest, EmptyShardsMergeAndAMergedFailureExits1) {
  const std::string run = torusRun("2.0,3.0");  // two groups
  const CliRun whole = osteon("validate " + run + " --out-dir " + quoted(path("whole")));
  ASSERT_EQ(whole.exitCode, 0) << whole.err;
  const json empty = shard(run, 2, 3, "t2");
  EXPECT_TRUE(empty["cases"].empty());
  EXPECT_TRUE(empty["shard"]["cases"].empty());
  EXPECT_EQ(empty["shard"]["case_list"].size(), 8u);
  EXPECT_EQ(empty["verdict"], "PASS");
  shard(run, 0, 3, "t0");
  shard(run, 1, 3, "t1");
  const CliRun merge = osteon(mergeArgs({"t2", "t0", "t1"}, "m"));  // any order
  ASSERT_EQ(merge.exitCode, 0) << merge.err;
  EXPECT_EQ(casesWithoutTimes(report("m")), casesWithoutTimes(report("whole")));
  EXPECT_EQ(report("m")["merged_from"], json({path("t0"), path("t1"), path("t2")}));

  // A crack-free case that failed in one shard fails the merged run.
  std::filesystem::create_directories(path("t0fail"));
  json failed = report("t0");
  ASSERT_FALSE(failed["cases"].empty());
  failed["cases"][0]["pass"] = false;
  failed["cases"][0]["failures"] = {"before drilling: 1 border edges"};
  test::writeBytes(path("t0fail/report.json"), failed.dump());
  const CliRun failing = osteon(mergeArgs({"t0fail", "t1", "t2"}, "mf"));
  EXPECT_EQ(failing.exitCode, 1) << failing.err;
  EXPECT_EQ(report("mf")["verdict"], "FAIL");
}

// Shards that are not one run are refused, each naming the folders and the reason.
TEST_F(ValidateShardTest, MergeRefusesShardsThatAreNotOneRun) {
  const std::string run = torusRun("2.0,3.0");
  shard(run, 0, 2, "a0");
  shard(run, 1, 2, "a1");
  shard(torusRun("3.0"), 1, 2, "other1");  // another case list
  shard(run, 0, 3, "three0");              // another split

  expectBadInput(mergeArgs({"a0"}, "m"), "shard 1/2", "missing");
  expectBadInput(mergeArgs({"a0", "a1", "a1"}, "m"), path("a1") + " and " + path("a1"),
                 "both shard 1/2");
  expectBadInput(mergeArgs({"a0", "other1"}, "m"), path("a0") + " and " + path("other1"),
                 "case lists differ");
  expectBadInput(mergeArgs({"a0", "a1", "three0"}, "m"), path("three0"), "different splits");

  // Another osteon version: a copy of a shard with its version edited.
  std::filesystem::create_directories(path("old1"));
  json older = report("a1");
  older["osteon_version"] = "0.0.1";
  test::writeBytes(path("old1/report.json"), older.dump());
  expectBadInput(mergeArgs({"a0", "old1"}, "m"), path("old1"), "different osteon versions");

  // Folders that hold no shard report.
  std::filesystem::create_directories(path("nothing"));
  expectBadInput(mergeArgs({"a0", "nothing"}, "m"), path("nothing"), "no report.json");
  std::filesystem::create_directories(path("broken"));
  test::writeBytes(path("broken/report.json"),
                   test::readBytes(path("a1/report.json")).substr(0, 100));
  expectBadInput(mergeArgs({"a0", "broken"}, "m"), path("broken"), "not JSON");
  const CliRun whole = osteon("validate " + run + " --out-dir " + quoted(path("whole")));
  ASSERT_EQ(whole.exitCode, 0) << whole.err;
  expectBadInput(mergeArgs({"a0", "whole"}, "m"), path("whole"), "not a shard report");
  std::filesystem::create_directories(path("cut"));
  json cut = report("a0");
  ASSERT_FALSE(cut["cases"].empty());
  cut["cases"].erase(cut["cases"].size() - 1);
  test::writeBytes(path("cut/report.json"), cut.dump());
  expectBadInput(mergeArgs({"cut", "a1"}, "m"), path("cut"), "its shard names");
  std::filesystem::create_directories(path("typed"));
  json typed = report("a0");
  typed["cases"][1]["border_edges"] = "none";
  test::writeBytes(path("typed/report.json"), typed.dump());
  expectBadInput(mergeArgs({"typed", "a1"}, "m"), path("typed"),
                 "\"border_edges\" is not a number");

  // Nothing written over a shard, and a merge takes no run options.
  expectBadInput(mergeArgs({"a0", "a1"}, "a0"), "--out-dir " + path("a0"), "is the shard folder");
  expectBadInput(mergeArgs({"a0", "a1"}, "m") + " --quick", "--quick", "not of a merge");
  EXPECT_FALSE(std::filesystem::exists(path("m")));
}

TEST_F(ValidateShardTest, BadShardValuesGiveExitCode2) {
  for (const char* bad : {"3/3", "-1/2", "a/b", "0/0", "1", "1/", "/2", "1/2/3", "+1/2", "0/-2"}) {
    expectBadInput("validate --quick --shard " + quoted(bad) + " --out-dir " + quoted(path("v")),
                   std::string("--shard ") + bad, "");
  }
  expectBadInput("validate --quick --shard 3/3 --out-dir " + quoted(path("v")), "--shard 3/3",
                 "below N");
  expectBadInput("validate --quick --shard 0/0 --out-dir " + quoted(path("v")), "--shard 0/0",
                 "at least 1");
  expectBadInput("validate --quick --shard a/b --out-dir " + quoted(path("v")), "--shard a/b",
                 "not K/N");
  // A model given twice would give two cases one key: a merge could not tell them apart.
  expectBadInput(
      "validate --quick --models default,default --shard 0/2 --out-dir " + quoted(path("v")),
      "default|1.2|crackfree|static", "comes twice");
  EXPECT_FALSE(std::filesystem::exists(path("v/report.json")));
}

}  // namespace
}  // namespace osteon
