// The validate report reader (cli/src/report_reader.h) on its own: the nesting bound, the type
// and range of fields, the names a report may list, and the fuzzer's seed, which must stay a
// report both readers take (tests/fuzz/fuzz_report_json.cpp starts from it).
#include "report_reader.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "osteon/core/error.h"
#include "support/files.h"

namespace osteon::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class ReportReaderTest : public ::testing::Test {
 protected:
  std::string dir_ = osteon::test::makeTempDir("report_reader");
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  static json seed() {
    std::ifstream in(std::string(OSTEON_SOURCE_DIR) + "/tests/data/seeds/report.json");
    return json::parse(in);
  }

  // The InputError message of reading `report` as --compare, or "" when it is taken.
  std::string compareError(const json& report) const {
    try {
      readComparable(write("old.json", report.dump()));
      return "";
    } catch (const InputError& e) {
      return e.what();
    }
  }

  std::string shardError(const json& report) const {
    try {
      readShard("s", write("report.json", report.dump()));
      return "";
    } catch (const InputError& e) {
      return e.what();
    }
  }
};

TEST_F(ReportReaderTest, TheFuzzSeedIsAReportBothReadersTake) {
  const json r = seed();
  EXPECT_EQ(compareError(r), "");
  EXPECT_EQ(shardError(r), "");
  EXPECT_EQ(readShard("s", write("report.json", r.dump())).report["cases"].size(), 4u);
}

TEST_F(ReportReaderTest, NestingIsBoundedAtTheLimitExactly) {
  const auto nested = [](int levels) {
    return std::string(std::size_t(levels), '[') + std::string(std::size_t(levels), ']');
  };
  EXPECT_TRUE(readReportJson(write("ok.json", nested(kMaxReportDepth)), "--compare x").is_array());
  try {
    readReportJson(write("deep.json", nested(kMaxReportDepth + 1)), "--compare x");
    FAIL() << "one level too deep was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nests deeper than 64 levels"), std::string::npos)
        << e.what();
  }
  // Objects count as levels too, and strings that look like brackets do not.
  std::string objects = "1";
  for (int i = 0; i < kMaxReportDepth + 1; ++i) objects = "{\"a\":" + objects + "}";
  EXPECT_THROW(readReportJson(write("objects.json", objects), "--compare x"), InputError);
  EXPECT_NO_THROW(
      readReportJson(write("text.json", "[\"" + std::string(1000, '[') + "\"]"), "--compare x"));
  EXPECT_THROW(readReportJson(write("cut.json", "{\"a\":"), "--compare x"), InputError);
  EXPECT_THROW(readReportJson(dir_, "--compare x"), InputError);  // a folder
}

TEST_F(ReportReaderTest, FieldsAreCheckedForTypeAndRange) {
  const auto withCase = [](const char* field, const json& value) {
    json r = seed();
    r["cases"][1][field] = value;
    return r;
  };
  EXPECT_NE(compareError(withCase("border_edges", 1e300))
                .find("case 1 (labels.nrrd|2|crackfree|dynamic): \"border_edges\" is 1e+300"),
            std::string::npos);
  EXPECT_EQ(compareError(withCase("border_edges", 18446744073709551615ULL)), "");
  EXPECT_NE(compareError(withCase("border_edges", -3)), "");
  EXPECT_NE(
      compareError(withCase("crack_percent", "0.5")).find("\"crack_percent\" is not a number"),
      std::string::npos);
  EXPECT_NE(compareError(withCase("crack_percent", 100.5)), "");
  EXPECT_EQ(compareError(withCase("crack_percent", 100)), "");
  EXPECT_EQ(compareError(withCase("hausdorff_mm", nullptr)), "");
  EXPECT_EQ(compareError(withCase("jitter_n", nullptr)), "");  // a run's NaN jitter
  EXPECT_EQ(shardError(withCase("max_force_n", nullptr)), "");
  EXPECT_NE(compareError(withCase("pass", 1)).find("\"pass\" is not true or false"),
            std::string::npos);
  // An old report may lack a compared field; a shard's report may not.
  json lacking = seed();
  lacking["cases"][1].erase("jitter_n");
  EXPECT_EQ(compareError(lacking), "");
  EXPECT_NE(shardError(lacking).find("\"jitter_n\" is missing"), std::string::npos);
  json after = seed();
  after["cases"][0]["after"]["crack_percent"] = -1;
  EXPECT_NE(shardError(after).find("\"after.crack_percent\" is -1"), std::string::npos);
  json slow = seed();
  slow["seconds"] = kMaxRunSeconds * 2;
  EXPECT_NE(shardError(slow).find("\"seconds\""), std::string::npos);
  json huge = seed();
  huge["shard"]["count"] = 1000000000;
  EXPECT_NE(shardError(huge).find("not a shard report"), std::string::npos);
}

TEST_F(ReportReaderTest, ListedOutputsArePlainNamesInTheirFolder) {
  EXPECT_TRUE(isReportOutputPath("images/0_crackfree/cracks_+x.png", "images"));
  EXPECT_TRUE(isReportOutputPath("plots/default_VS_1.2_mm_5.png", "plots"));
  for (const char* bad :
       {"images/../x.png", "images/.hidden.png", "images/a b.png", "images/x' onerror='a.png",
        "images/", "images//x.png", "plots/x.png", "/images/x.png", "images/a\"b.png"}) {
    EXPECT_FALSE(isReportOutputPath(bad, "images")) << bad;
  }
}

}  // namespace
}  // namespace osteon::cli
