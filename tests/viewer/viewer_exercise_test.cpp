// Exercises in the viewer under Xvfb: a built-in one played along its ideal path scores full
// marks through the same API as `osteon score`, and its three bad attempts fail for their
// reasons; one read from a JSON file opens with its plan drawn over the bone (green axis and
// entry pixels in the frame); bad ones are refused with one line before any window. Skipped,
// with the reason, when no X server can start.
#include <cstdlib>
#include <filesystem>
#include <future>
#include <memory>
#include <stb/stb_image.h>  // the implementation is in viewer_scope_test.cpp
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "igtl/igtl_client.h"
#include "support/exercise_attempts.h"
#include "support/files.h"
#include "support/process.h"
#include "viewer_fixture.h"

namespace osteon {
namespace {

using nlohmann::json;

// Pixels of the plan's and the entry's green in a PNG.
std::size_t greenPixels(const std::string& png) {
  int w = 0, h = 0, channels = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> rgb(stbi_load(png.c_str(), &w, &h, &channels, 3),
                                                      stbi_image_free);
  if (!rgb) return 0;
  std::size_t green = 0;
  for (std::size_t i = 0; i < std::size_t(w) * std::size_t(h); ++i) {
    const unsigned char* p = rgb.get() + 3 * i;
    if (p[1] > 180 && p[0] < 140 && p[2] < 170) ++green;
  }
  return green;
}

class ViewerExerciseTest : public test::ViewerFixture {
 protected:
  ViewerExerciseTest() : ViewerFixture("viewer_exercise") {}

  json viewer(const std::string& args, const std::string& png) const {
    const test::ProcessRun r = run(args + " --json --screenshot '" + path(png) + "'");
    EXPECT_EQ(r.exitCode, 0) << args << "\n" << r.err;
    keepShot(png);
    return r.exitCode == 0 ? json::parse(r.out) : json::object();
  }
};

TEST_F(ViewerExerciseTest, ThePlanPathScoresFullMarksInTheViewer) {
  const json j = viewer(
      "--exercise anchor-5 --path plan --frames 20 --camera left --focus tool "
      "--zoom 3",
      "viewer_exercise_score.png");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["exercise"], "anchor-5");
  const json& s = j["score"];
  ASSERT_TRUE(s.is_object()) << j.dump();
  EXPECT_TRUE(s["passed"].get<bool>()) << s.dump(2);
  EXPECT_DOUBLE_EQ(s["score"].get<double>(), 100.0);
  std::vector<std::string> names;
  for (const json& c : s["criteria"]) {
    names.push_back(c["name"].get<std::string>());
    EXPECT_TRUE(c["passed"].get<bool>()) << c.dump();
  }
  EXPECT_EQ(names, (std::vector<std::string>{"entry", "angle", "depth", "overcut", "no_go", "force",
                                             "time"}));
  EXPECT_GT(j["removed_volume_mm3"].get<double>(), 50.0);
}

// The three bad attempts played from path CSVs, as `osteon score` plays them: each fails on its
// own criterion (and overcut, since the hole is elsewhere), and the deep one cuts the far cortex.
TEST_F(ViewerExerciseTest, TheThreeBadAttemptsFailForTheirReasons) {
  struct Bad {
    const char* name;
    test::AttemptChange change;
    std::vector<std::string> failing;
  };
  const Bad attempts[] = {{"tilt", test::thirtyDegreesOffAxis, {"angle", "overcut"}},
                          {"off", test::entryFiveMillimetresOff, {"entry", "overcut"}},
                          {"deep", test::tenMillimetresTooDeep, {"depth", "overcut", "no_go"}}};
  for (const Bad& bad : attempts) {
    const std::string csv = path(std::string(bad.name) + ".csv");
    test::writeBytes(csv, test::attemptCsv("anchor-5", bad.change));
    const json j = viewer("--exercise anchor-5 --path '" + csv + "' --frames 5 --no-ui",
                          std::string("viewer_exercise_") + bad.name + ".png");
    ASSERT_TRUE(j.contains("score") && j["score"].is_object()) << bad.name << ": " << j.dump();
    const json& s = j["score"];
    EXPECT_FALSE(s["passed"].get<bool>()) << bad.name;
    std::vector<std::string> failed;
    for (const json& c : s["criteria"])
      if (!c["passed"].get<bool>()) failed.push_back(c["name"].get<std::string>());
    EXPECT_EQ(failed, bad.failing) << bad.name << ": " << s.dump(2);
    double farMm3 = 0.0;
    for (const json& b : s["no_go"])
      if (b["zone"] == "far_cortex") farMm3 = b["volume_mm3"].get<double>();
    if (std::string(bad.name) == "deep") {
      EXPECT_GT(farMm3, 0.5);
    } else {
      EXPECT_EQ(farMm3, 0.0) << bad.name;
    }
  }
}

// With --igtl the score reaches the OpenIGTLink clients as STRING Score (one line) and
// ScoreDetails (the score's JSON), and the report counts the link.
TEST_F(ViewerExerciseTest, TheScoreIsSentOverOpenIgtLink) {
  auto client = std::async(std::launch::async, [] { return test::receiveAll(18984); });
  const json j = viewer("--exercise anchor-5 --path plan --frames 20 --igtl 18984",
                        "viewer_exercise_igtl.png");
  ASSERT_FALSE(j.empty());
  const test::IgtlReceived got = client.get();
  ASSERT_TRUE(j["igtl"].is_object()) << j.dump();
  EXPECT_EQ(j["igtl"]["clients"], 1);
  EXPECT_EQ(j["igtl"]["messages_sent"], got.messages);
  std::string score, details;
  for (const std::string& s : got.strings) {
    if (s.rfind("Score=", 0) == 0) score = s.substr(6);
    if (s.rfind("ScoreDetails=", 0) == 0) details = s.substr(13);
  }
  EXPECT_EQ(score.rfind("PASSED, score ", 0), 0u) << score;
  ASSERT_FALSE(details.empty());
  EXPECT_EQ(json::parse(details), j["score"]);
  EXPECT_EQ(got.wholeVolumes, 1);
}

// An exercise from a file: portal 7, 15 mm deep. The mouse has not drilled: the plan is drawn
// (green: the axis and the entry marker), and the score at exit fails.
TEST_F(ViewerExerciseTest, AnExerciseFileOpensWithItsPlanDrawn) {
  test::writeBytes(path("hole-7.json"), R"({
  "title": "A test hole from the 7 o'clock portal",
  "instructions": "Drill 15 mm along the plan.",
  "bone": {"input": "default", "units": "mm", "voxel_size_mm": 1.2},
  "levels": 2, "tool": "drill", "portal": "portal-7",
  "axis": {"angle_deg": 45}, "depth_mm": 15, "diameter_mm": 2.92,
  "force_limit_n": 3.0, "time_limit_s": 60
})");
  const json j = viewer("--exercise '" + path("hole-7.json") +
                            "' --frames 5 --no-ui --camera left --focus tool --zoom 3",
                        "viewer_exercise_file.png");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["exercise"], "hole-7");
  ASSERT_TRUE(j["score"].is_object());
  EXPECT_FALSE(j["score"]["passed"].get<bool>());
  EXPECT_GT(greenPixels(path("viewer_exercise_file.png")), 40u);
}

// Without an exercise the humeral head the resting pose was fitted to and the portal's entry
// are drawn too: the entry's green ball shows beside the tool.
TEST_F(ViewerExerciseTest, WithoutAnExerciseTheHeadAndTheEntryAreDrawn) {
  const json j = viewer("default --frames 5 --no-ui --camera left --focus tool --zoom 2",
                        "viewer_head_entry.png");
  ASSERT_FALSE(j.empty());
  EXPECT_TRUE(j["exercise"].is_null());
  EXPECT_GT(greenPixels(path("viewer_head_entry.png")), 40u);
}

TEST_F(ViewerExerciseTest, BadExercisesAreRefusedWithOneLine) {
  for (const std::string& args :
       {std::string("--exercise nonsense-9"), std::string("--exercise '") + path("none.json") + "'",
        std::string("default --path plan")}) {
    const test::ProcessRun r = run(args, false);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
  }
}

}  // namespace
}  // namespace osteon
