// Error metrics of `voxgi compare` on inputs with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/log.h"
#include "image/metrics.h"

namespace voxgi::image {
namespace {

Image constant(int w, int h, int channels, float v) {
  Image img;
  img.width = w;
  img.height = h;
  img.channels = channels;
  img.pixels.assign(static_cast<size_t>(w) * static_cast<size_t>(h) * static_cast<size_t>(channels),
                    v);
  return img;
}

TEST(Metrics, IdenticalImages) {
  Image a = constant(20, 16, 3, 0.0f);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 2.0f);
  for (float& v : a.pixels) v = u(rng);
  const ErrorMetrics m = errorMetrics(a, a);
  EXPECT_EQ(m.rmse, 0.0);
  EXPECT_EQ(m.relMse, 0.0);
  EXPECT_TRUE(std::isinf(m.psnr));
  EXPECT_NEAR(m.ssim, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(m.meanLuminanceRatio, 1.0);
}

TEST(Metrics, ConstantOffsetHasClosedForms) {
  const Image test = constant(16, 16, 3, 0.5f), ref = constant(16, 16, 3, 0.6f);
  const ErrorMetrics m = errorMetrics(test, ref);
  EXPECT_NEAR(m.rmse, 0.1, 1e-6);
  EXPECT_NEAR(m.relMse, 0.01 / (0.36 + kRelMseEpsilon), 1e-6);
  EXPECT_NEAR(m.psnr, 20.0, 1e-4);  // 10 log10(1 / 0.01)
  // Flat windows: SSIM reduces to the luminance term (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1).
  const double c1 = 1e-4;
  EXPECT_NEAR(m.ssim, (2 * 0.5 * 0.6 + c1) / (0.25 + 0.36 + c1), 1e-6);
  EXPECT_NEAR(m.meanLuminanceRatio, 0.5 / 0.6, 1e-6);
  EXPECT_NEAR(m.meanLuminanceTest, 0.5, 1e-6);
}

TEST(Metrics, LuminanceUsesRec709AndGreyIsItself) {
  Image red = constant(4, 4, 3, 0.0f);
  for (size_t i = 0; i < red.pixels.size(); i += 3) red.pixels[i] = 1.0f;
  EXPECT_NEAR(luminance(red)[0], 0.2126, 1e-9);
  EXPECT_NEAR(luminance(constant(4, 4, 1, 0.25f))[5], 0.25, 1e-9);
}

TEST(Metrics, SsimFallsWithNoiseAndIgnoresAlpha) {
  Image ref = constant(32, 32, 4, 0.0f), noisy = ref;
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> n(0.0f, 0.1f);
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    ref.pixels[i] = (i % 4 == 3) ? 1.0f : 0.5f + 0.3f * std::sin(0.3f * static_cast<float>(i / 4));
    noisy.pixels[i] = (i % 4 == 3) ? u(rng) : ref.pixels[i] + n(rng);
  }
  const ErrorMetrics m = errorMetrics(noisy, ref);
  EXPECT_LT(m.ssim, 0.97);
  EXPECT_GT(m.ssim, 0.0);
  EXPECT_NEAR(m.rmse, 0.1, 0.01);  // colour only: the random alpha does not count
}

TEST(Metrics, BlackReference) {
  const ErrorMetrics m = errorMetrics(constant(8, 8, 3, 0.0f), constant(8, 8, 3, 0.0f));
  EXPECT_DOUBLE_EQ(m.meanLuminanceRatio, 1.0);
  EXPECT_TRUE(std::isinf(
      errorMetrics(constant(8, 8, 3, 1.0f), constant(8, 8, 3, 0.0f)).meanLuminanceRatio));
}

TEST(Metrics, MismatchesAreOneLineErrors) {
  try {
    errorMetrics(constant(8, 8, 3, 0.0f), constant(8, 9, 3, 0.0f));
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "images differ in size: 8x8 vs 8x9");
  }
  try {
    errorMetrics(constant(8, 8, 3, 0.0f), constant(8, 8, 4, 0.0f));
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "images differ in channel count: 3 vs 4");
  }
}

// One 16x16 block of a 40x36 image (blocks of 16: 3 x 3, the last row and column
// partial) made 1.5x brighter, and one partial block 0.5x: the extremes are those
// blocks, where they are; the whole image's mean hides both.
TEST(Metrics, BlockRatiosFindTheBlockThatIsOff) {
  const Image ref = constant(40, 36, 3, 0.4f);
  Image test = ref;
  auto set = [&](int x0, int y0, int x1, int y1, float v) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        for (int c = 0; c < 3; ++c) test.pixels[(static_cast<size_t>(y) * 40 + x) * 3 + c] = v;
  };
  set(16, 0, 32, 16, 0.6f);   // block (16, 0): 1.5x
  set(32, 32, 40, 36, 0.2f);  // the bottom-right partial block: 0.5x
  const BlockRatios b = blockRatios(test, ref, 16);
  EXPECT_EQ(b.blocks, 9);
  EXPECT_EQ(b.skipped, 0);
  EXPECT_NEAR(b.max, 1.5, 1e-6);
  EXPECT_EQ(b.maxX, 16);
  EXPECT_EQ(b.maxY, 0);
  EXPECT_NEAR(b.min, 0.5, 1e-6);
  EXPECT_EQ(b.minX, 32);
  EXPECT_EQ(b.minY, 32);
  EXPECT_NEAR(b.over3Percent, 2.0 / 9.0, 1e-12);
  EXPECT_NEAR(b.over10Percent, 2.0 / 9.0, 1e-12);
  // A small change (2%) counts in neither share.
  set(16, 0, 32, 16, 0.408f);
  set(32, 32, 40, 36, 0.4f);
  const BlockRatios near = blockRatios(test, ref, 16);
  EXPECT_NEAR(near.max, 1.02, 1e-6);
  EXPECT_EQ(near.over3Percent, 0.0);
}

// Blocks too dark in the reference to measure are left out, not divided by ~0.
TEST(Metrics, BlockRatiosSkipBlackBlocks) {
  Image ref = constant(32, 16, 3, 0.5f);
  for (int y = 0; y < 16; ++y)
    for (int x = 16; x < 32; ++x)
      for (int c = 0; c < 3; ++c) ref.pixels[(static_cast<size_t>(y) * 32 + x) * 3 + c] = 0.0f;
  const BlockRatios b = blockRatios(constant(32, 16, 3, 0.5f), ref, 16);
  EXPECT_EQ(b.blocks, 1);
  EXPECT_EQ(b.skipped, 1);
  EXPECT_DOUBLE_EQ(b.max, 1.0);
  EXPECT_THROW(blockRatios(ref, ref, 0), Error);
  EXPECT_THROW(blockRatios(ref, constant(16, 16, 3, 0.5f), 16), Error);
}

}  // namespace
}  // namespace voxgi::image
