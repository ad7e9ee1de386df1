// Image files and differences, without a GL context.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/log.h"
#include "image/image.h"
#include "image/metrics.h"
#include "support/test_paths.h"

namespace voxgi::image {
namespace {
namespace fs = std::filesystem;

TEST(ImageIo, PngRoundTripsBytesAndOrientation) {
  const std::string dir = test::scratchDir();
  std::vector<uint8_t> px(3 * 2 * 4);
  for (size_t i = 0; i < px.size(); ++i) px[i] = static_cast<uint8_t>(i * 10);
  writePng(dir + "/a.png", 3, 2, px.data());
  const Image img = readImage(dir + "/a.png");
  ASSERT_EQ(img.width, 3);
  ASSERT_EQ(img.height, 2);
  ASSERT_EQ(img.channels, 3);  // alpha is not stored
  for (size_t p = 0; p < 6; ++p)
    for (size_t c = 0; c < 3; ++c)
      EXPECT_NEAR(img.pixels[p * 3 + c] * 255.0f, px[p * 4 + c], 1e-3) << p;
}

// A 16-bit PNG keeps its precision: 0.3 is stored as 19661/65535, where 8 bits
// would give 77/255 = 0.302. The file was made with `oiiotool --pattern
// constant:color=0.3 2x1 1 -d uint16 -o grey16.png`.
TEST(ImageIo, SixteenBitPngReadsAtFullPrecision) {
  const Image img = readImage(test::testDataDir() + "/images/grey16.png");
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 1);
  ASSERT_EQ(img.channels, 1);
  for (float v : img.pixels) EXPECT_NEAR(v, 0.3f, 1e-4f);
}

TEST(ImageIo, ExrKeepsLinearFloats) {
  const std::string dir = test::scratchDir();
  std::vector<float> px = {0.0f, 1.5f, 100.0f, 1.0f, 1e-4f, 0.25f, 15.0f, 1.0f};
  writeExr(dir + "/a.exr", 2, 1, px.data());
  const Image img = readImage(dir + "/a.exr");
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.channels, 3);
  for (size_t p = 0; p < 2; ++p)
    for (size_t c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(img.pixels[p * 3 + c], px[p * 4 + c]);
}

TEST(ImageIo, RefusesBadPathsWithoutTouchingFiles) {
  const std::string dir = test::scratchDir();
  std::vector<uint8_t> px(4, 255);
  EXPECT_THROW(writePng(dir + "/missing/a.png", 1, 1, px.data()), Error);
  EXPECT_THROW(formatForPath(dir + "/a.tga"), Error);
  EXPECT_THROW(checkWritable(dir), Error);
  EXPECT_TRUE(fs::is_empty(dir));
  EXPECT_THROW(readImage(dir + "/none.png"), Error);
}

TEST(ImageIo, ReplacesAnExistingFileOnlyWhenComplete) {
  const std::string dir = test::scratchDir();
  std::vector<uint8_t> px(4, 7);
  writePng(dir + "/a.png", 1, 1, px.data());
  px.assign(4, 9);
  writePng(dir + "/a.png", 1, 1, px.data());
  EXPECT_NEAR(readImage(dir + "/a.png").pixels[0] * 255.0f, 9.0f, 1e-3);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()),
            1);  // no temp left
}

TEST(Metrics, CompareKnownDifferences) {
  Image a, b;
  a.width = b.width = 2;
  a.height = b.height = 1;
  a.channels = b.channels = 3;
  a.pixels = {0, 0, 0, 1, 1, 1};
  b.pixels = {0, 0, 0, 1, 1, 0.5f};
  const Difference d = compare(a, b, 0.1);
  EXPECT_DOUBLE_EQ(d.maxAbs, 0.5);
  EXPECT_NEAR(d.meanAbs, 0.5 / 6.0, 1e-12);
  EXPECT_NEAR(d.rmse, std::sqrt(0.25 / 6.0), 1e-12);
  EXPECT_DOUBLE_EQ(d.fractionAbove, 0.5);
  b.width = 1;
  EXPECT_THROW(compare(a, b, 0.1), Error);
}

}  // namespace
}  // namespace voxgi::image
