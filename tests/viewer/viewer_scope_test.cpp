// The arthroscope's view in a real window under Xvfb, read back from --screenshot: bone inside
// its circular field, lit by its spotlight, and black outside the circle; and the same view in
// the corner as picture-in-picture. Skipped, with the reason, when no X server can start.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

#include "support/files.h"
#include "support/process.h"
#include "viewer_fixture.h"

namespace osteon {
namespace {

struct Image {
  int width = 0, height = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> rgb{nullptr, stbi_image_free};
  const unsigned char* at(int x, int y) const {
    return rgb.get() + 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
  }
};

Image readPng(const std::string& path) {
  Image image;
  int channels = 0;
  image.rgb.reset(stbi_load(path.c_str(), &image.width, &image.height, &channels, 3));
  return image;
}

// Bone as shaded: warm (red >= green >= blue, red clearly above blue) and not dark.
bool boneColoured(const unsigned char* p) {
  return p[0] >= 60 && p[0] >= p[1] && p[1] >= p[2] && p[0] - p[2] >= 8;
}

// Pixels inside and outside the circle of `radius` about (cx, cy), with a 3 px margin.
struct FieldCounts {
  std::size_t inside = 0, insideBone = 0, outside = 0, outsideNotBlack = 0;
};

FieldCounts countField(const Image& image, double cx, double cy, double radius, int x0, int y0,
                       int x1, int y1) {
  FieldCounts c;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const double r = std::hypot(double(x) + 0.5 - cx, double(y) + 0.5 - cy);
      const unsigned char* p = image.at(x, y);
      if (r < radius - 3.0) {
        ++c.inside;
        if (boneColoured(p)) ++c.insideBone;
      } else if (r > radius + 3.0) {
        ++c.outside;
        if (p[0] > 2 || p[1] > 2 || p[2] > 2) ++c.outsideNotBlack;
      }
    }
  }
  return c;
}

class ViewerScopeTest : public test::ViewerFixture {
 protected:
  ViewerScopeTest() : ViewerFixture("viewer_scope") {}

  // Runs the viewer and returns its last frame.
  Image shot(const std::string& args, const std::string& png) const {
    const test::ProcessRun r =
        test::runShell("xvfb-run -a -s '-screen 0 1280x800x24' timeout 300 '" OSTEON_VIEWER "' " +
                           args + " --frames 5 --json --screenshot '" + path(png) + "'",
                       path("stdout"), path("stderr"));
    EXPECT_EQ(r.exitCode, 0) << args << "\n" << r.err;
    keepShot(png);
    return readPng(path(png));
  }
};

// The scope at the 5 o'clock portal looks at the humeral head: bone fills much of its circle,
// and everything outside the circle is black.
TEST_F(ViewerScopeTest, TheArthroscopeShowsBoneInsideItsCircularField) {
  const Image image =
      shot("default --camera scope --no-ui --no-tool --size 640x480", "viewer_scope_field.png");
  ASSERT_EQ(image.width, 640);
  ASSERT_EQ(image.height, 480);
  const double radius = 0.96 * 240.0;  // Arthroscope::kFieldRadiusNdc of half the height
  const FieldCounts c = countField(image, 320.0, 240.0, radius, 0, 0, 640, 480);
  EXPECT_GT(double(c.insideBone), 0.25 * double(c.inside));
  EXPECT_GT(c.outside, 50000u);
  EXPECT_EQ(c.outsideNotBlack, 0u);
  // The spotlight: the brightest bone is far brighter than the dimmest lit bone.
  int brightest = 0;
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) brightest = std::max<int>(brightest, image.at(x, y)[0]);
  EXPECT_GT(brightest, 180);
}

// A second device drives the scope: the scripted portal-7 path puts its tip and shaft where
// the path's drill starts, so the field shows the head from elsewhere than the default aim.
TEST_F(ViewerScopeTest, ASecondDeviceDrivesTheArthroscope) {
  const std::string view = "default --camera scope --no-ui --no-tool --size 640x480";
  const Image aimed = shot(view, "viewer_scope_aimed.png");
  const Image driven = shot(view + " --scope-device scripted:portal-7", "viewer_scope_device.png");
  ASSERT_EQ(driven.width, 640);
  const double radius = 0.96 * 240.0;
  const FieldCounts c = countField(driven, 320.0, 240.0, radius, 0, 0, 640, 480);
  EXPECT_GT(double(c.insideBone), 0.05 * double(c.inside));
  EXPECT_EQ(c.outsideNotBlack, 0u);
  std::size_t differing = 0;
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) {
      const unsigned char *a = aimed.at(x, y), *b = driven.at(x, y);
      if (std::abs(int(a[0]) - int(b[0])) > 40) ++differing;
    }
  EXPECT_GT(differing, 10000u);
}

// The orbit view with the scope in the top right corner: a square of side 2/5 of the height,
// 12 px from the edges, its own circle of bone on black.
TEST_F(ViewerScopeTest, PictureInPictureShowsTheScopeInTheCorner) {
  const Image image =
      shot("default --pip --no-ui --no-tool --size 800x600", "viewer_scope_pip.png");
  ASSERT_EQ(image.width, 800);
  const int side = 600 * 2 / 5, x0 = 800 - side - 12, y0 = 12;
  const double radius = 0.96 * 0.5 * side;
  const FieldCounts c =
      countField(image, x0 + 0.5 * side, y0 + 0.5 * side, radius, x0, y0, x0 + side, y0 + side);
  EXPECT_GT(double(c.insideBone), 0.2 * double(c.inside));
  EXPECT_GT(c.outside, 500u);
  EXPECT_EQ(c.outsideNotBlack, 0u);
  // The main view's background around it is not black.
  const unsigned char* p = image.at(20, 300);
  EXPECT_GT(int(p[0]) + int(p[1]) + int(p[2]), 30);
}

}  // namespace
}  // namespace osteon
