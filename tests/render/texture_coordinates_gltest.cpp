// Texture coordinates as glTF authors them, in every mode that shows a texture:
// TEXCOORD_1 where a texture's texCoord asks for it, KHR_texture_transform
// (offset, rotation, scale, its texCoord override), and each texture slot of a
// material reading its own mapping. The emissive quads of
// tests/data/texcoords (make_texcoords.py) fill the image; the expected image is
// computed here from the extension's formula and GL's NEAREST/REPEAT rules, without
// any of the code under test. Reading the wrong set, or a transform in the wrong
// order or direction, shows other texels over most of the image.
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

// 24 pixels a side: every texel edge the files' coordinates make (s or t a
// multiple of 1/4) falls on a pixel edge.
constexpr int kSize = 24;

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// make_texcoords.py's texture, NEAREST and REPEAT, at (u, v).
glm::vec3 texel(float u, float v) {
  const int i = ((static_cast<int>(std::floor(2.0f * u)) % 2) + 2) % 2;
  const int j = ((static_cast<int>(std::floor(2.0f * v)) % 2) + 2) % 2;
  const float lo = srgbToLinear(40.0f / 255.0f);
  return glm::vec3(i == 1 ? 1.0f : lo, j == 1 ? 1.0f : lo, 0.0f);
}

// The texture coordinates at the pixel whose right coordinates are (s, t): as they
// are, or through the files' transform, written out from the extension's matrix
// (offset (0.5, 1), rotation pi/2, scale (2, 1)):
//   u' = cos(r) sx s + sin(r) sy t + ox = t + 0.5
//   v' = -sin(r) sx s + cos(r) sy t + oy = 1 - 2 s
glm::vec2 expectedUv(bool transformed, float s, float t) {
  return transformed ? glm::vec2(t + 0.5f, 1.0f - 2.0f * s) : glm::vec2(s, t);
}

struct Case {
  const char* file;
  bool transformed;
};

// mixed_transforms.gltf and two_sets.gltf add a base-colour texture (black factor)
// on the other mapping: the emissive texture reads channel 1, and shows the other
// texels wherever it read the base colour's channel 0.
const Case kCases[] = {{"texcoord1.gltf", false},
                       {"transform.gltf", true},
                       {"transform_texcoord1.gltf", true},
                       {"mixed_transforms.gltf", true},
                       {"two_sets.gltf", false}};

class TextureCoordinatesTest : public GlTest {};

TEST_F(TextureCoordinatesTest, SetAndTransformInEveryMode) {
  for (const Case& c : kCases) {
    const scene::Scene s = scene::loadGltf(testDataDir() + "/texcoords/" + c.file);
    for (const ModeRun& run : kEveryMode) {
      SCOPED_TRACE(std::string(c.file) + ", " + run.name);
      render::RenderSettings rs;
      applyRun(run, &rs);
      rs.width = rs.height = kSize;
      rs.voxels = 32;
      rs.spp = 16;
      rs.jitter = false;
      gl::ProgramCache programs(sourceDir() + "/shaders");
      render::Renderer r(programs, s, rs);
      r.renderFrame();
      const std::vector<float> px = r.readLinear();
      int bad = 0;
      float worst = 0.0f;
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
          const float st = (static_cast<float>(x) + 0.5f) / kSize;
          const float tt = (static_cast<float>(y) + 0.5f) / kSize;
          const glm::vec2 uv = expectedUv(c.transformed, st, tt);
          const glm::vec3 want = texel(uv.x, uv.y);
          const size_t i = (static_cast<size_t>(y) * kSize + static_cast<size_t>(x)) * 4;
          const glm::vec3 got(px[i], px[i + 1], px[i + 2]);
          const float err = glm::length(got - want);
          worst = std::max(worst, err);
          if (err > 0.01f && bad++ < 4)
            ADD_FAILURE() << "pixel (" << x << ", " << y << "): got (" << got.r << ", " << got.g
                          << ", " << got.b << "), expected (" << want.r << ", " << want.g << ", "
                          << want.b << ")";
        }
      std::printf("%-26s %-14s worst error %.4f, %d pixels over 0.01\n", c.file, run.name, worst,
                  bad);
      EXPECT_EQ(bad, 0);
    }
  }
}

// The expected images can fail: untransformed or reversed readings differ from the
// transformed one over most of the image.
TEST(TextureCoordinatesExpected, WrongReadingsDiffer) {
  int differ = 0, reversed = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const float s = (static_cast<float>(x) + 0.5f) / kSize;
      const float t = (static_cast<float>(y) + 0.5f) / kSize;
      const glm::vec2 uv = expectedUv(true, s, t);
      const glm::vec3 want = texel(uv.x, uv.y);
      differ += texel(s, t) != want;                          // not transformed
      reversed += texel(-t + 0.5f, 1.0f + 2.0f * s) != want;  // rotated clockwise
    }
  EXPECT_GT(differ, kSize * kSize / 3);
  EXPECT_GT(reversed, kSize * kSize / 3);
}

}  // namespace
}  // namespace voxgi::test
