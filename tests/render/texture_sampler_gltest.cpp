// glTF sampler wrap modes and magnification filters, in every mode that shows a
// texture: the emissive quads of tests/data/samplers (make_samplers.py), whose UVs
// run from -1 to 2 across the image, show the 2 x 2 texture wrapped as each file's
// sampler says (REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT per axis; NEAREST or LINEAR)
// in raster and rtgi (GL samplers) and in the path tracer on both devices (the
// shared reads of texture_shared.h). The expected image is computed here, from
// GL's wrap rules, without any of the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/mode_runs.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

// 24 pixels a side: the quad's UVs span 3 periods, 8 pixels a period, so every
// texel edge (s or t a multiple of 1/2) falls on a pixel edge.
constexpr int kSize = 24;

enum class Wrap { kRepeat, kClamp, kMirror };

struct Case {
  const char* file;
  Wrap s, t;
  bool nearest;
};

const Case kCases[] = {
    {"wrap_repeat_repeat_nearest.gltf", Wrap::kRepeat, Wrap::kRepeat, true},
    {"wrap_clamp_clamp_nearest.gltf", Wrap::kClamp, Wrap::kClamp, true},
    {"wrap_mirror_mirror_nearest.gltf", Wrap::kMirror, Wrap::kMirror, true},
    {"wrap_clamp_mirror_nearest.gltf", Wrap::kClamp, Wrap::kMirror, true},
    {"wrap_mirror_repeat_linear.gltf", Wrap::kMirror, Wrap::kRepeat, false},
    {"wrap_repeat_clamp_linear.gltf", Wrap::kRepeat, Wrap::kClamp, false},
    {"no_sampler.gltf", Wrap::kRepeat, Wrap::kRepeat, false},
};

// GL's wrap of texel index i (any integer) on an axis of n texels.
int wrapIndex(int i, int n, Wrap w) {
  if (w == Wrap::kClamp) return std::clamp(i, 0, n - 1);
  if (w == Wrap::kMirror) {
    const int m = ((i % (2 * n)) + 2 * n) % (2 * n);
    return m < n ? m : 2 * n - 1 - m;
  }
  return ((i % n) + n) % n;
}

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// make_samplers.py's texture: red 255 in the right column (40 left), green 255 in
// the bottom row (40 top), decoded from sRGB.
glm::vec3 texel(int i, int j) {
  const float lo = srgbToLinear(40.0f / 255.0f);
  return glm::vec3(i == 1 ? 1.0f : lo, j == 1 ? 1.0f : lo, 0.0f);
}

// The texture at (s, t) as a GL sampler reads it (magnification).
glm::vec3 expected(const Case& c, float s, float t) {
  if (c.nearest)
    return texel(wrapIndex(static_cast<int>(std::floor(2.0f * s)), 2, c.s),
                 wrapIndex(static_cast<int>(std::floor(2.0f * t)), 2, c.t));
  const float x = 2.0f * s - 0.5f, y = 2.0f * t - 0.5f;
  const int i = static_cast<int>(std::floor(x)), j = static_cast<int>(std::floor(y));
  const float fx = x - static_cast<float>(i), fy = y - static_cast<float>(j);
  auto at = [&](int di, int dj) {
    return texel(wrapIndex(i + di, 2, c.s), wrapIndex(j + dj, 2, c.t));
  };
  return glm::mix(glm::mix(at(0, 0), at(1, 0), fx), glm::mix(at(0, 1), at(1, 1), fx), fy);
}

class TextureSamplerTest : public GlTest {};

TEST_F(TextureSamplerTest, WrapAndFilterInEveryMode) {
  for (const Case& c : kCases) {
    const scene::Scene s = scene::loadGltf(testDataDir() + "/samplers/" + c.file);
    for (const ModeRun& run : kEveryMode) {
      SCOPED_TRACE(std::string(c.file) + ", " + run.name);
      render::RenderSettings rs;
      applyRun(run, &rs);
      rs.width = rs.height = kSize;
      rs.voxels = 32;
      rs.spp = 64;
      rs.jitter = false;  // rtgi's single frame at the pixel centres
      gl::ProgramCache programs(sourceDir() + "/shaders");
      render::Renderer r(programs, s, rs);
      r.renderFrame();
      const std::vector<float> px = r.readLinear();
      // Raster and rtgi read at the pixel centre; the path tracer averages over the
      // pixel, which for a bilinear texture inside one cell is the centre's value
      // (up to its noise: 64 samples of a slope of at most 0.25 across the pixel).
      const float tolerance =
          run.mode == render::Mode::kPathtrace && !c.nearest ? 0.05f : (c.nearest ? 0.01f : 0.03f);
      float worst = 0.0f;
      int bad = 0;
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
          const float u = -1.0f + 3.0f * (static_cast<float>(x) + 0.5f) / kSize;
          const float v = -1.0f + 3.0f * (static_cast<float>(y) + 0.5f) / kSize;
          const glm::vec3 want = expected(c, u, v);
          const size_t i = (static_cast<size_t>(y) * kSize + static_cast<size_t>(x)) * 4;
          const glm::vec3 got(px[i], px[i + 1], px[i + 2]);
          const float err = glm::length(got - want);
          worst = std::max(worst, err);
          if (err > tolerance && bad++ < 4)
            ADD_FAILURE() << "pixel (" << x << ", " << y << ") at uv (" << u << ", " << v
                          << "): got (" << got.r << ", " << got.g << ", " << got.b
                          << "), expected (" << want.r << ", " << want.g << ", " << want.b << ")";
        }
      std::printf("%-34s %-14s worst error %.4f, %d pixels over %.2f\n", c.file, run.name, worst,
                  bad, tolerance);
      EXPECT_EQ(bad, 0);
    }
  }
}

// The wrap modes are told apart: the same pixel reads another texel under each (a
// check that the expected images themselves differ, so the test above can fail).
TEST(TextureSamplerExpected, ModesDiffer) {
  // s = -0.375 (left of the quad): REPEAT reads the right texel's red 1, CLAMP the
  // left edge's, MIRRORED_REPEAT (s -> 0.375) the left texel too; s = 1.125: REPEAT
  // left, CLAMP right, MIRROR right.
  const Case repeat{"", Wrap::kRepeat, Wrap::kRepeat, true};
  const Case clamp{"", Wrap::kClamp, Wrap::kClamp, true};
  const Case mirror{"", Wrap::kMirror, Wrap::kMirror, true};
  EXPECT_EQ(expected(repeat, -0.375f, 0.25f).r, 1.0f);
  EXPECT_LT(expected(clamp, -0.375f, 0.25f).r, 0.1f);
  EXPECT_LT(expected(mirror, -0.375f, 0.25f).r, 0.1f);
  EXPECT_LT(expected(repeat, 1.125f, 0.25f).r, 0.1f);
  EXPECT_EQ(expected(clamp, 1.125f, 0.25f).r, 1.0f);
  EXPECT_EQ(expected(mirror, 1.125f, 0.25f).r, 1.0f);
  EXPECT_EQ(expected(mirror, -0.875f, 0.25f).r, 1.0f);  // mirrored: 0.875, right texel
}

}  // namespace
}  // namespace voxgi::test
