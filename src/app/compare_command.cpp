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
  try {
    m = image::errorMetrics(test, ref);
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
  return 0;
}

}  // namespace voxgi::app
