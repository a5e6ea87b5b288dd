// osteon-viewer driven by real X input (xdotool's XTEST events) under Xvfb: the fixture the
// hand tests share. Skipped, with the reason, when Xvfb or xdotool is missing (scripts/setup
// installs both). Set OSTEON_VIEWER_SHOTS=DIR to keep the screenshots.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/files.h"
#include "support/process.h"
#include "viewer_fixture.h"

namespace osteon::test {

using nlohmann::json;

class ViewerHand : public ViewerFixture {
 protected:
  ViewerHand() : ViewerFixture("viewer_hand", true) {}

  // Opens the viewer on `bone` (the built-in one) with the mouse tool, plays `input` (shell lines
  // of xdotool; $pid is the viewer's process) to its window, closes it with Esc and Enter (Esc asks
  // first), and returns its --json. The last frame goes to `png` (kept in OSTEON_VIEWER_SHOTS when
  // set).
  json hand(const std::string& args, const std::string& input, const std::string& png,
            const std::string& bone = "default --voxel-size 1.2 --levels 2") const {
    const std::string script =
        "'" OSTEON_VIEWER "' " + bone + " --size 1024x700 " + args + " --json --screenshot '" +
        path(png) + "' >'" + path("stdout") + "' 2>'" + path("stderr") +
        "' </dev/null &\n"
        "pid=$!\n"
        "wid=$(timeout 120 xdotool search --sync --name '^osteon-viewer' | head -n 1)\n"
        "if [ -z \"$wid\" ]; then kill $pid; wait $pid; exit 97; fi\n"
        "xdotool windowfocus \"$wid\"; sleep 1\n"
        "xdotool mousemove --window \"$wid\" 700 350\n" +  // over the bone's side, clear of the
                                                           // panels
        input +
        "xdotool key Escape; sleep 0.5; xdotool key Return\n"
        "wait $pid\n";
    test::writeBytes(path("hand.sh"), script);
    const int code = test::runShell("xvfb-run -a -s '-screen 0 1280x800x24' timeout 120 sh '" +
                                        path("hand.sh") + "'",
                                    path("xvfb.out"), path("xvfb.err"))
                         .exitCode;
    EXPECT_EQ(code, 0) << args << "\n" << test::readBytes(path("stderr"));
    keepShot(png);
    EXPECT_GT(test::readBytes(path(png)).size(), 10000u);
    return code == 0 ? json::parse(test::readBytes(path("stdout"))) : json::object();
  }
};

}  // namespace osteon::test
