// The viewer's key table, key scripts, exposure steps and screenshot names, without
// a window.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "app/screenshot.h"
#include "app/viewer_input.h"
#include "core/log.h"
#include "render/renderer.h"
#include "support/test_paths.h"

namespace voxgi::app {
namespace {
namespace fs = std::filesystem;
using K = Action::Kind;

TEST(ViewerInput, ModeSlotsInTheDocumentedOrder) {
  EXPECT_STREQ(modeForSlot(1), "raster");
  EXPECT_STREQ(modeForSlot(2), "points");
  EXPECT_STREQ(modeForSlot(3), "dvr");
  EXPECT_STREQ(modeForSlot(4), "rtgi");
  EXPECT_STREQ(modeForSlot(5), "pathtrace");
  EXPECT_EQ(modeForSlot(6), nullptr);  // reserved
  EXPECT_EQ(modeForSlot(0), nullptr);
  EXPECT_EQ(modeForSlot(7), nullptr);
  // Every mode this build has sits in a slot.
  EXPECT_TRUE(render::parseMode(modeForSlot(1)).has_value());
}

TEST(ViewerInput, KeyNamesRoundTrip) {
  for (const char* name :
       {"1", "2", "3", "4", "5", "6", "+", "-", "t", "r", "p", "m", "n", "tab", "esc"}) {
    const auto a = actionForKeyName(name);
    ASSERT_TRUE(a.has_value()) << name;
    EXPECT_EQ(keyName(*a), name);
  }
  EXPECT_EQ(*actionForKeyName("3"), (Action{K::kMode, 3}));
  EXPECT_FALSE(actionForKeyName("7").has_value());
  EXPECT_FALSE(actionForKeyName("0").has_value());
  EXPECT_FALSE(actionForKeyName("x").has_value());
  EXPECT_FALSE(actionForKeyName("").has_value());
}

TEST(ViewerInput, KeyScriptParsesAndSorts) {
  const auto s = parseKeyScript("20:1,10:2,10:+,30:esc,");
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].frame, 10);
  EXPECT_EQ(s[0].action, (Action{K::kMode, 2}));
  EXPECT_EQ(s[1].frame, 10);  // same frame: kept in the order given
  EXPECT_EQ(s[1].action.kind, K::kExposureUp);
  EXPECT_EQ(s[2].frame, 20);
  EXPECT_EQ(s[3].action.kind, K::kQuit);
}

TEST(ViewerInput, BadKeyScriptsNameTheEntry) {
  auto message = [](const std::string& script) {
    try {
      parseKeyScript(script);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("").find("empty"), std::string::npos);
  EXPECT_NE(message("10").find("'10' is not FRAME:KEY"), std::string::npos);
  EXPECT_NE(message("10:2,x:1").find("'x:1'"), std::string::npos);
  EXPECT_NE(message("0:1").find("from 1"), std::string::npos);
  EXPECT_NE(message("-3:1").find("from 1"), std::string::npos);
  EXPECT_NE(message("5:z").find("unknown key 'z'"), std::string::npos);
  EXPECT_NE(message("5:1,,6:2").find("empty"), std::string::npos);
}

TEST(ViewerInput, ExposureStepsAreHalfStops) {
  EXPECT_FLOAT_EQ(stepExposure(1.0f, 1), std::sqrt(2.0f));
  EXPECT_EQ(stepExposure(stepExposure(1.0f, 1), 1), 2.0f);  // exact: stops are rounded
  EXPECT_EQ(stepExposure(stepExposure(1.0f, 1), -1), 1.0f);
  EXPECT_EQ(stepExposure(1.0f, -2), 0.5f);
  // An exposure between half stops snaps to the grid on its next step.
  EXPECT_EQ(stepExposure(1.9f, 1), std::exp2(1.5f));
}

TEST(Screenshot, ExplicitNamesGiveAPair) {
  auto p = screenshotPathsFor("out/shot.png");
  EXPECT_EQ(p.png, "out/shot.png");
  EXPECT_EQ(p.exr, "out/shot.exr");
  p = screenshotPathsFor("shot.exr");
  EXPECT_EQ(p.png, "shot.png");
  EXPECT_EQ(p.exr, "shot.exr");
  p = screenshotPathsFor("shot");
  EXPECT_EQ(p.png, "shot.png");
  EXPECT_EQ(p.exr, "shot.exr");
  p = screenshotPathsFor("shot.jpg");
  EXPECT_EQ(p.png, "shot.jpg.png");
}

TEST(Screenshot, AutomaticNamesNeverOverwrite) {
  const std::string dir = test::scratchDir();
  std::tm t{};
  t.tm_year = 2024 - 1900;
  t.tm_mon = 4;
  t.tm_mday = 6;
  t.tm_hour = 7;
  t.tm_min = 8;
  t.tm_sec = 9;
  t.tm_isdst = -1;
  const std::time_t when = std::mktime(&t);
  auto p = nextScreenshotPaths(dir, when);
  EXPECT_EQ(fs::path(p.png).filename(), "voxgi-20240506-070809-1.png");
  EXPECT_EQ(fs::path(p.exr).filename(), "voxgi-20240506-070809-1.exr");
  std::ofstream(p.png) << "x";
  p = nextScreenshotPaths(dir, when);
  EXPECT_EQ(fs::path(p.png).filename(), "voxgi-20240506-070809-2.png");
  // Either file of a pair being there is enough to move on.
  std::ofstream(p.exr) << "x";
  p = nextScreenshotPaths(dir, when);
  EXPECT_EQ(fs::path(p.png).filename(), "voxgi-20240506-070809-3.png");
  EXPECT_EQ(fs::path(nextScreenshotPaths("", when).png).parent_path(), ".");
}

}  // namespace
}  // namespace voxgi::app
