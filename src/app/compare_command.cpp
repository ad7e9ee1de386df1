// `voxgi compare TEST REF [--json]`: error metrics of a linear image against a
// reference (image/metrics.h defines them).
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "image/image.h"
#include "image/metrics.h"

namespace voxgi::app {
namespace {

image::Image load(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error(path + ": no such file");
  if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, not an image");
  return image::readImage(path);
}

// JSON has no infinity: identical images give a PSNR of null.
nlohmann::ordered_json finiteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

}  // namespace

int runCompare(const CompareOptions& o) {
  const image::Image test = load(o.test);
  const image::Image ref = load(o.reference);
  image::ErrorMetrics m;
  image::BlockRatios b;
  try {
    m = image::errorMetrics(test, ref);
    if (o.blocks > 0) b = image::blockRatios(test, ref, o.blocks);
  } catch (const Error& e) {
    throw Error(o.test + " vs " + o.reference + ": " + e.what());
  }
  if (o.json) {
    nlohmann::ordered_json j;
    j["test"] = o.test;
    j["reference"] = o.reference;
    j["width"] = test.width;
    j["height"] = test.height;
    j["channels"] = test.channels;
    j["rmse"] = m.rmse;
    j["rel_mse"] = m.relMse;
    j["psnr"] = finiteOrNull(m.psnr);
    j["ssim"] = m.ssim;
    j["mean_luminance_test"] = m.meanLuminanceTest;
    j["mean_luminance_reference"] = m.meanLuminanceReference;
    j["mean_luminance_ratio"] = finiteOrNull(m.meanLuminanceRatio);
    if (o.blocks > 0) {
      j["block_size"] = b.block;
      j["blocks"] = b.blocks;
      j["blocks_skipped"] = b.skipped;
      j["block_ratio_min"] = b.min;
      j["block_ratio_min_at"] = {b.minX, b.minY};
      j["block_ratio_max"] = b.max;
      j["block_ratio_max_at"] = {b.maxX, b.maxY};
      j["blocks_off_3_percent"] = b.over3Percent;
      j["blocks_off_10_percent"] = b.over10Percent;
    }
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("%s vs %s (%dx%d, %d channels)\n", o.test.c_str(), o.reference.c_str(), test.width,
              test.height, test.channels);
  std::printf("  rmse                  %.6g\n", m.rmse);
  std::printf("  rel_mse               %.6g\n", m.relMse);
  std::printf("  psnr                  %.2f dB\n", m.psnr);
  std::printf("  ssim                  %.4f\n", m.ssim);
  std::printf("  mean_luminance_ratio  %.4f  (%.6g / %.6g)\n", m.meanLuminanceRatio,
              m.meanLuminanceTest, m.meanLuminanceReference);
  if (o.blocks > 0)
    std::printf(
        "  %dx%d blocks          %d measured (%d too dark): ratio %.4f at (%d, %d) to %.4f at "
        "(%d, %d); %.1f%% off by > 3%%, %.1f%% by > 10%%\n",
        b.block, b.block, b.blocks, b.skipped, b.min, b.minX, b.minY, b.max, b.maxX, b.maxY,
        100.0 * b.over3Percent, 100.0 * b.over10Percent);
  return 0;
}

}  // namespace voxgi::app
