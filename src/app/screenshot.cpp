#include "app/screenshot.h"

#include <filesystem>

#include "core/log.h"

namespace voxgi::app {
namespace fs = std::filesystem;

ScreenshotPaths screenshotPathsFor(const std::string& file) {
  const fs::path p(file);
  const std::string ext = p.extension().string();
  if (ext == ".png" || ext == ".exr") {
    fs::path png = p, exr = p;
    png.replace_extension(".png");
    exr.replace_extension(".exr");
    return {png.string(), exr.string()};
  }
  return {file + ".png", file + ".exr"};
}

ScreenshotPaths nextScreenshotPaths(const std::string& dir, std::time_t now) {
  std::tm local{};
  localtime_r(&now, &local);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%d-%H%M%S", &local);
  const fs::path base = dir.empty() ? fs::path(".") : fs::path(dir);
  for (int n = 1;; ++n) {
    const fs::path stem = base / strf("voxgi-%s-%d", stamp, n);
    ScreenshotPaths p{stem.string() + ".png", stem.string() + ".exr"};
    std::error_code ec;
    if (!fs::exists(p.png, ec) && !fs::exists(p.exr, ec)) return p;
  }
}

}  // namespace voxgi::app
