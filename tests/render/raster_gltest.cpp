// Raster baseline on llvmpipe: EGL and OSMesa agree, the Cornell room matches its
// golden image, and the golden tolerance is tight enough that a moved light or a
// swapped material breaks it. Set VOXGI_UPDATE_GOLDEN=1 to rewrite the golden.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "gl/debug.h"
#include "image/image.h"
#include "image/metrics.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

constexpr int kSize = 128;
// Golden tolerance: mean error under 1 LSB and at most 1% of pixels off by more
// than 3 LSB (llvmpipe versions may round differently at edges).
constexpr double kMeanTolerance = 1.0 / 255.0;
constexpr double kPixelThreshold = 3.0 / 255.0;
constexpr double kPixelFraction = 0.01;

std::string goldenPath() {
  return testDataDir() + "/golden/cornell_room_raster_128.png";
}

struct Rendered {
  std::vector<uint8_t> rgba;  // as read back
  image::Image display;       // 8-bit sRGB as [0,1], RGB as the PNG stores it
  std::vector<float> linear;
};

Rendered render(const scene::Scene& s) {
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::RenderSettings settings;
  settings.mode = render::Mode::kRaster;
  settings.width = kSize;
  settings.height = kSize;
  render::Renderer r(programs, s, settings);
  r.renderFrame();
  Rendered out;
  const auto px = r.readDisplay();
  out.display.width = kSize;
  out.display.height = kSize;
  out.display.channels = 3;  // as PNGs are stored
  for (size_t i = 0; i < px.size(); ++i)
    if (i % 4 != 3) out.display.pixels.push_back(px[i] / 255.0f);
  out.linear = r.readLinear();
  out.rgba = px;
  return out;
}

bool withinGolden(const image::Difference& d) {
  return d.meanAbs <= kMeanTolerance && d.fractionAbove <= kPixelFraction;
}

class RasterTest : public GlBackendTest {};

TEST_P(RasterTest, CornellRoomMatchesGolden) {
  const scene::Scene s = scene::loadGltf(cornellRoom());
  const Rendered r = render(s);
  for (float v : r.linear) ASSERT_TRUE(std::isfinite(v));
  if (std::getenv("VOXGI_UPDATE_GOLDEN")) {
    image::writePng(goldenPath(), kSize, kSize, r.rgba.data());
  }
  ASSERT_TRUE(std::filesystem::exists(goldenPath()))
      << "run with VOXGI_UPDATE_GOLDEN=1 to create " << goldenPath();
  const image::Image golden = image::readImage(goldenPath());
  const image::Difference d = image::compare(r.display, golden, kPixelThreshold);
  EXPECT_TRUE(withinGolden(d)) << "mean " << d.meanAbs * 255 << " LSB, " << d.fractionAbove * 100
                               << "% pixels over 3 LSB, max " << d.maxAbs * 255 << " LSB";
}

INSTANTIATE_TEST_SUITE_P(Headless, RasterTest,
                         ::testing::Values(gl::Backend::kEgl, gl::Backend::kOsMesa),
                         backendParamName);

// Both backends in one process, one after the other: the images agree within 1 LSB.
TEST(RasterBackends, EglAndOsMesaAgree) {
  const scene::Scene s = scene::loadGltf(cornellRoom());
  std::string why;
  image::Image a, b;
  {
    auto ctx = makeContext(gl::Backend::kEgl, &why);
    ASSERT_TRUE(ctx) << why;
    a = render(s).display;
    EXPECT_EQ(gl::debugErrorCount(), 0) << gl::lastDebugError();
  }
  {
    auto ctx = makeContext(gl::Backend::kOsMesa, &why);
    if (!ctx) {
      if (std::getenv("VOXGI_REQUIRE_OSMESA")) FAIL() << why;
      GTEST_SKIP() << why;
    }
    b = render(s).display;
    EXPECT_EQ(gl::debugErrorCount(), 0) << gl::lastDebugError();
  }
  const image::Difference d = image::compare(a, b, 1.0 / 255.0 + 1e-6);
  EXPECT_LE(d.maxAbs, 1.0 / 255.0 + 1e-6) << "max " << d.maxAbs * 255 << " LSB";
}

// The tolerance above must catch real regressions.
class RasterSensitivityTest : public GlTest {
 protected:
  image::Difference differenceFromGolden(const scene::Scene& s) {
    const image::Image golden = image::readImage(goldenPath());
    const image::Difference d = image::compare(render(s).display, golden, kPixelThreshold);
    std::printf("difference from golden: mean %.2f LSB, %.2f%% of pixels over 3 LSB\n",
                d.meanAbs * 255, d.fractionAbove * 100);
    return d;
  }
};

TEST_F(RasterSensitivityTest, MovedLightBreaksTolerance) {
  scene::Scene s = scene::loadGltf(cornellRoom());
  // Move the ceiling light by 20 cm along x (its vertices are shared by its triangles).
  int moved = 0;
  std::vector<bool> done(s.vertices.size(), false);
  for (const scene::Draw& d : s.draws) {
    if (!s.materials[static_cast<size_t>(d.material)].isEmissive()) continue;
    for (uint32_t i = d.firstIndex; i < d.firstIndex + d.indexCount; ++i) {
      if (done[s.indices[i]]) continue;
      done[s.indices[i]] = true;
      s.vertices[s.indices[i]].position.x += 0.2f;
      ++moved;
    }
  }
  ASSERT_EQ(moved, 4);
  const image::Difference d = differenceFromGolden(s);
  EXPECT_FALSE(withinGolden(d)) << "a light moved by 20 cm passed the golden check: mean "
                                << d.meanAbs * 255 << " LSB, " << d.fractionAbove * 100 << "%";
}

TEST_F(RasterSensitivityTest, SwappedMaterialBreaksTolerance) {
  scene::Scene s = scene::loadGltf(cornellRoom());
  // Swap the red and the green wall.
  int red = -1, green = -1;
  for (size_t i = 0; i < s.materials.size(); ++i) {
    const glm::vec4 c = s.materials[i].baseColor;
    if (c.r > 0.5f && c.g < 0.2f) red = static_cast<int>(i);
    if (c.g > 0.4f && c.r < 0.2f) green = static_cast<int>(i);
  }
  ASSERT_GE(red, 0);
  ASSERT_GE(green, 0);
  std::swap(s.materials[static_cast<size_t>(red)], s.materials[static_cast<size_t>(green)]);
  const image::Difference d = differenceFromGolden(s);
  EXPECT_FALSE(withinGolden(d));
}

TEST_F(RasterSensitivityTest, DimmerLightBreaksTolerance) {
  scene::Scene s = scene::loadGltf(cornellRoom());
  for (scene::Material& m : s.materials) m.emission *= 0.9f;  // 10% less light
  const image::Difference d = differenceFromGolden(s);
  EXPECT_FALSE(withinGolden(d)) << "mean " << d.meanAbs * 255 << " LSB, " << d.fractionAbove * 100
                                << "%";
}

}  // namespace
}  // namespace voxgi::test
