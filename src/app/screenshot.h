// Where the viewer's screenshots go. Each is a pair: PNG (what the window shows,
// tonemapped sRGB 8-bit) and EXR (linear radiance) with the same base name.
//  - The screenshot key: voxgi-YYYYmmdd-HHMMSS-N.{png,exr} in the screenshot folder,
//    N the smallest number from 1 for which neither file exists: nothing earlier is
//    ever overwritten.
//  - An explicit `--screenshot FILE` is what the user asked for: like `render --out`,
//    an existing file is replaced, once the new one is complete.
#ifndef VOXGI_APP_SCREENSHOT_H
#define VOXGI_APP_SCREENSHOT_H

#include <ctime>
#include <string>

namespace voxgi::app {

struct ScreenshotPaths {
  std::string png;
  std::string exr;
};

// FILE.png or FILE.exr: that file and its sibling; any other name gets both
// extensions appended (shot -> shot.png + shot.exr).
ScreenshotPaths screenshotPathsFor(const std::string& file);

// The next free automatic name in `dir` for the local time `now`.
ScreenshotPaths nextScreenshotPaths(const std::string& dir, std::time_t now);

}  // namespace voxgi::app

#endif  // VOXGI_APP_SCREENSHOT_H
