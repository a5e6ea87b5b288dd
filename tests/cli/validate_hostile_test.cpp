// Validate reports osteon did not write itself, as an attacker or a careless hand edits them:
// `validate --compare OLD.json` and `validate --merge DIR...` refuse them (exit 2, one line
// naming the file, the case and the field), never crash, never write outside --out-dir, and
// report.html never carries markup from a report.
#include <filesystem>
#include <string>
#include <sys/stat.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "osteon/geometry/io/mesh_io.h"
#include "support/cli_fixture.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

class ValidateHostileTest : public CliTest {
 protected:
  // One shard (0/1) of a torus at one size: four cases, checked but not drilled, about a second.
  void SetUp() override {
    geometry::writeMesh(test::makeTorus(20.0, 7.0, 48, 24), path("torus.stl"));
    const CliRun r = osteon("validate --quick --models " + quoted(path("torus.stl")) +
                            " --voxel-sizes 3.0 --shard 0/1 --out-dir " + quoted(path("s0")));
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    shard_ = json::parse(test::readBytes(path("s0/report.json")));
    ASSERT_EQ(shard_["cases"].size(), 4u);
  }

  std::string merge(const std::string& dir, const std::string& out) const {
    return "validate --merge " + quoted(path(dir)) + " --out-dir " + quoted(path(out));
  }

  // A shard folder holding `report` as its report.json.
  void writeShard(const std::string& dir, const json& report) const {
    fs::create_directories(path(dir));
    test::writeBytes(path(dir + "/report.json"), report.dump());
  }

  json shard_;
};

// 200,000 levels of arrays: nlohmann parses them without recursion, but its copy and dump
// recurse once per level, and the merge segfaulted in both.
TEST_F(ValidateHostileTest, DeeplyNestedReportsAreRefusedNotACrash) {
  json report = shard_;
  report["cases"][0]["portals"] = "@deep@";
  std::string text = report.dump();
  text.replace(text.find("\"@deep@\""), 8, std::string(200000, '[') + std::string(200000, ']'));
  test::writeBytes(path("deep.json"), text);
  fs::create_directories(path("deep"));
  test::writeBytes(path("deep/report.json"), text);

  expectBadInput(merge("s0", "m") + " --compare " + quoted(path("deep.json")),
                 "--compare " + path("deep.json"), "nests deeper than 64 levels");
  expectBadInput(merge("deep", "m"), "--merge " + path("deep") + ": report.json",
                 "nests deeper than 64 levels");
  // A run refuses it before running.
  expectBadInput("validate --quick --models " + quoted(path("torus.stl")) +
                     " --voxel-sizes 3.0 --out-dir " + quoted(path("v")) + " --compare " +
                     quoted(path("deep.json")),
                 path("deep.json"), "nests deeper than 64 levels");
  EXPECT_FALSE(fs::exists(path("m")));
  EXPECT_FALSE(fs::exists(path("v/report.json")));
}

// A link in a shard's output folders was followed, and the copy landed at a path made from the
// link's target: outside --out-dir, over an unrelated file, with exit 0 and PASS.
TEST_F(ValidateHostileTest, MergeRefusesLinksAndSpecialFilesInAShardAndWritesOnlyInsideOutDir) {
  fs::create_directories(path("secret"));
  test::writeBytes(path("secret/data.csv"), "the link's target\n");
  fs::create_directories(path("deep/secret"));
  test::writeBytes(path("deep/secret/data.csv"), "an unrelated file\n");
  fs::create_symlink(path("secret/data.csv"), path("s0/forces/evil.csv"));
  expectBadInput(merge("s0", "deep/out"), "--merge " + path("s0") + ": forces/evil.csv",
                 "symbolic link");
  EXPECT_EQ(test::readBytes(path("deep/secret/data.csv")), "an unrelated file\n");
  EXPECT_EQ(test::readBytes(path("secret/data.csv")), "the link's target\n");
  EXPECT_FALSE(fs::exists(path("deep/out")))
      << "nothing written before every shard file is checked";
  fs::remove(path("s0/forces/evil.csv"));

  // A link deeper down, a linked folder, and a FIFO (which would block a reader).
  fs::create_symlink(path("secret/data.csv"), path("s0/images/0_crackfree/x.png"));
  expectBadInput(merge("s0", "out"), "images/0_crackfree/x.png", "symbolic link");
  fs::remove(path("s0/images/0_crackfree/x.png"));
  fs::rename(path("s0/plots"), path("realplots"));
  fs::create_directory_symlink(path("realplots"), path("s0/plots"));
  expectBadInput(merge("s0", "out"), "--merge " + path("s0") + ": plots", "symbolic link");
  fs::remove(path("s0/plots"));
  fs::rename(path("realplots"), path("s0/plots"));
  ASSERT_EQ(::mkfifo(path("s0/forces/pipe.csv").c_str(), 0600), 0);
  expectBadInput(merge("s0", "out"), "forces/pipe.csv", "not a regular file");
  fs::remove(path("s0/forces/pipe.csv"));
  fs::rename(path("s0/validate.log"), path("validate.log"));
  fs::create_symlink(path("secret/data.csv"), path("s0/validate.log"));
  expectBadInput(merge("s0", "out"), "validate.log", "symbolic link");
  fs::remove(path("s0/validate.log"));
  fs::rename(path("validate.log"), path("s0/validate.log"));
  EXPECT_FALSE(fs::exists(path("out")));

  // A link already in --out-dir where a copy goes is not written through.
  fs::create_directories(path("out"));
  fs::create_directory_symlink(path("secret"), path("out/forces"));
  expectBadInput(merge("s0", "out"), "--out-dir " + path("out") + ": forces",
                 "not a folder of its own");
  fs::remove(path("out/forces"));
  test::writeBytes(path("s0/forces/a.csv"), "t,f\n");
  fs::create_directories(path("out/forces"));
  fs::create_symlink(path("secret/data.csv"), path("out/forces/a.csv"));
  const CliRun ok = osteon(merge("s0", "out"));
  ASSERT_EQ(ok.exitCode, 0) << ok.err;
  EXPECT_FALSE(fs::is_symlink(path("out/forces/a.csv")));
  EXPECT_EQ(test::readBytes(path("out/forces/a.csv")), "t,f\n");
  EXPECT_EQ(test::readBytes(path("secret/data.csv")), "the link's target\n");
}

// --compare cast counts to int (1e300 became -2147483648, a false regression) and skipped a
// field of the wrong type silently.
TEST_F(ValidateHostileTest, CompareRefusesFieldsOfTheWrongTypeOrRange) {
  const auto compareWith = [&](const std::string& field, const json& value) {
    json old = shard_;
    old["cases"][0][field] = value;
    test::writeBytes(path("old.json"), old.dump());
    return merge("s0", "m") + " --compare " + quoted(path("old.json"));
  };
  const std::string where = "--compare " + path("old.json") + ": case 0 (";
  expectBadInput(compareWith("border_edges", 1e300), where,
                 "\"border_edges\" is 1e+300, not a whole count");
  expectBadInput(compareWith("border_edges", -1), where,
                 "\"border_edges\" is -1, not a whole count");
  expectBadInput(compareWith("border_edges", 2.5), where, "\"border_edges\" is 2.5");
  expectBadInput(compareWith("collision_misses", "3"), where,
                 "\"collision_misses\" is not a number");
  expectBadInput(compareWith("crack_percent", "12"), where, "\"crack_percent\" is not a number");
  expectBadInput(compareWith("crack_percent", 250.0), where,
                 "\"crack_percent\" is 250.0, not a percentage");
  expectBadInput(compareWith("jitter_n", -0.5), where,
                 "\"jitter_n\" is -0.5, not a finite number of at least 0");
  expectBadInput(compareWith("hausdorff_mm", "far"), where, "\"hausdorff_mm\" is not a number");
  expectBadInput(compareWith("voxel_size_mm", 0), "--compare " + path("old.json") + ": case 0",
                 "\"voxel_size_mm\" is 0");
  expectBadInput(compareWith("model", 7), "--compare " + path("old.json") + ": case 0",
                 "\"model\" is not a string");
  EXPECT_FALSE(fs::exists(path("m")));

  // Counts past 32 bits compare as counts: a rise is a regression with its true numbers.
  json now = shard_;
  now["cases"][0]["border_edges"] = 4294967298ULL;
  writeShard("big", now);
  json old = shard_;
  old["cases"][0]["border_edges"] = 4294967297ULL;
  test::writeBytes(path("old.json"), old.dump());
  const CliRun compared = osteon(merge("big", "m") + " --compare " + quoted(path("old.json")));
  ASSERT_EQ(compared.exitCode, 0) << compared.err;
  const json m = json::parse(test::readBytes(path("m/report.json")));
  ASSERT_EQ(m["regressions"].size(), 1u) << m["regressions"];
  EXPECT_EQ(m["regressions"][0]["what"], "border_edges 4294967297 -> 4294967298");
}

// Image names sat in single-quoted attributes that the escaping left open: a name
// `x' onerror='alert(1)` ran script. Listed names must be plain; every shown value is escaped.
TEST_F(ValidateHostileTest, ReportHtmlCarriesNoMarkupFromAShard) {
  json hostile = shard_;
  hostile["images"].push_back("images/x' onerror='alert(1).png");
  writeShard("img", hostile);
  expectBadInput(merge("img", "m"), "--merge " + path("img"), "\"images\" lists");
  hostile = shard_;
  hostile["plots"].push_back("plots/../../x.png");
  writeShard("plot", hostile);
  expectBadInput(merge("plot", "m"), "--merge " + path("plot"), "\"plots\" lists");
  EXPECT_FALSE(fs::exists(path("m")));

  // Text a report may hold (a model's name, a failure) shows as text, quotes and all.
  const std::string payload = "x' onerror='alert(1)\" <script>alert(2)</script>";
  std::string text = shard_.dump();
  const std::string model = shard_["cases"][0]["model"].get<std::string>();
  const std::string inJson =
      json(payload).dump().substr(1, json(payload).dump().size() - 2);  // unquoted
  for (std::size_t at = text.find(model); at != std::string::npos;
       at = text.find(model, at + inJson.size())) {
    text.replace(at, model.size(), inJson);
  }
  json renamed = json::parse(text);
  renamed["cases"][1]["failures"] = {payload};
  writeShard("named", renamed);
  const CliRun run = osteon(merge("named", "m"));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const std::string html = test::readBytes(path("m/report.html"));
  EXPECT_NE(html.find("x&#39; onerror=&#39;alert(1)&quot; &lt;script&gt;"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("onerror='"), std::string::npos);
  EXPECT_EQ(html.find("='"), std::string::npos) << "every attribute is double-quoted";
}

// Timings must be a run's (finite, not negative, at most a year), and a run with no cases must
// not merge into a PASS.
TEST_F(ValidateHostileTest, MergeRefusesImplausibleTimesAndARunWithoutCases) {
  for (const json& seconds : {json(-1.0), json(1e308), json("12")}) {
    json bad = shard_;
    bad["seconds"] = seconds;
    writeShard("t", bad);
    expectBadInput(merge("t", "m"), "--merge " + path("t"), "\"seconds\"");
  }
  json slow = shard_;
  slow["cases"][2]["mesh_time_ms"]["total"] = -5.0;
  writeShard("t", slow);
  expectBadInput(merge("t", "m"), "case 2", "\"mesh_time_ms.total\" is -5.0");

  json empty = shard_;
  empty["cases"] = json::array();
  empty["shard"]["cases"] = json::array();
  empty["shard"]["case_list"] = json::array();
  writeShard("e", empty);
  expectBadInput(merge("e", "m"), "--merge " + path("e"), "no cases");
  EXPECT_FALSE(fs::exists(path("m")));
}

// report.json records the shard folders and the compared file by name, and JSON is UTF-8: a
// name that is not was an internal error (exit 3) once the merge was done.
TEST_F(ValidateHostileTest, NamesReportJsonCannotRecordAreRefusedUpFront) {
  fs::create_directory_symlink(path("s0"), path("s\xff"));
  expectBadInput(merge("s\xff", "m"), "--merge " + path("s\xff"), "not UTF-8");
  fs::copy_file(path("s0/report.json"), path("old\xff.json"));
  expectBadInput(merge("s0", "m") + " --compare " + quoted(path("old\xff.json")), "--compare",
                 "not UTF-8");
  EXPECT_FALSE(fs::exists(path("m")));
}

}  // namespace
}  // namespace osteon
