// glTF occlusionTexture in the raster baseline only: it darkens the ambient term
// (RenderSettings::ambient) by the texture's red channel, mixed in by its strength;
// direct light is left alone, and the GI modes, which compute their own occlusion,
// ignore it. The white quads of tests/data/texcoords/occlusion_strength_{0,1}.gltf
// (make_texcoords.py): occlusion 0 in the left half, 1 in the right; and
// occlusion_texcoord1.gltf, an occlusion texture on TEXCOORD_1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

constexpr int kSize = 16;
constexpr float kAmbient = 0.5f;

std::vector<float> render(const std::string& file, render::Mode mode, float ambient,
                          render::PathtraceDevice device = render::PathtraceDevice::kAuto) {
  const scene::Scene s = scene::loadGltf(testDataDir() + "/texcoords/" + file);
  render::RenderSettings rs;
  rs.mode = mode;
  rs.width = rs.height = kSize;
  rs.voxels = 32;
  rs.spp = 4;
  rs.jitter = false;
  rs.ambient = ambient;
  rs.pathtrace.device = device;
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::Renderer r(programs, s, rs);
  r.renderFrame();
  return r.readLinear();
}

// Mean red of the left or right half (the quad is white: red = green = blue).
float halfMean(const std::vector<float>& px, bool left) {
  double sum = 0.0;
  for (int y = 0; y < kSize; ++y)
    for (int x = left ? 0 : kSize / 2; x < (left ? kSize / 2 : kSize); ++x)
      sum += px[(static_cast<size_t>(y) * kSize + static_cast<size_t>(x)) * 4];
  return static_cast<float>(sum / (kSize * kSize / 2));
}

float maxDifference(const std::vector<float>& a, const std::vector<float>& b) {
  float d = 0.0f;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return a.size() == b.size() ? d : 1e30f;
}

class OcclusionTest : public GlTest {};

// Strength 1: the occluded half loses the whole ambient term (white albedo: 0.5),
// the other keeps it; strength 0: the texture does nothing.
TEST_F(OcclusionTest, DarkensTheRasterAmbientTerm) {
  const auto full = render("occlusion_strength_1.gltf", render::Mode::kRaster, kAmbient);
  const auto none = render("occlusion_strength_0.gltf", render::Mode::kRaster, kAmbient);
  const auto unlit = render("occlusion_strength_1.gltf", render::Mode::kRaster, 0.0f);
  std::printf("raster: left %.4f / %.4f, right %.4f / %.4f (strength 1 / 0), no ambient %.4f\n",
              halfMean(full, true), halfMean(none, true), halfMean(full, false),
              halfMean(none, false), halfMean(unlit, true));
  EXPECT_NEAR(halfMean(none, true) - halfMean(full, true), kAmbient, 1e-3f);
  EXPECT_NEAR(halfMean(full, false), halfMean(none, false), 1e-5f);
  EXPECT_NEAR(halfMean(full, true), halfMean(unlit, true), 1e-5f);  // direct light kept
  EXPECT_NEAR(halfMean(none, true), halfMean(none, false), 1e-5f);
  // Without ambient light the occlusion texture changes nothing.
  EXPECT_LT(maxDifference(unlit, render("occlusion_strength_0.gltf", render::Mode::kRaster, 0.0f)),
            1e-6f);
}

// An occlusion texture on another set than the base colour's reads its own
// (texture-coordinate channel 1): occlusion_texcoord1.gltf's occlusion map is the
// base colour's texture flipped, so the right half, red 1 in the base colour, has
// occlusion 40/255 (linear) where the base colour's coordinates would give 1. The
// ambient term alone: the render with ambient light less the one without.
TEST_F(OcclusionTest, ReadsItsOwnTextureCoordinates) {
  const auto lit = render("occlusion_texcoord1.gltf", render::Mode::kRaster, kAmbient);
  const auto unlit = render("occlusion_texcoord1.gltf", render::Mode::kRaster, 0.0f);
  const float ambientRight = halfMean(lit, false) - halfMean(unlit, false);
  std::printf("raster: ambient term in the right half %.4f (occlusion 40/255: %.4f)\n",
              ambientRight, kAmbient * 40.0f / 255.0f);
  EXPECT_NEAR(ambientRight, kAmbient * 40.0f / 255.0f, 2e-3f);
}

TEST_F(OcclusionTest, GiModesIgnoreIt) {
  struct Run {
    const char* name;
    render::Mode mode;
    render::PathtraceDevice device;
  };
  for (const Run& run :
       {Run{"rtgi", render::Mode::kRtgi, render::PathtraceDevice::kAuto},
        Run{"pathtrace gl", render::Mode::kPathtrace, render::PathtraceDevice::kGl},
        Run{"pathtrace cpu", render::Mode::kPathtrace, render::PathtraceDevice::kCpu}}) {
    SCOPED_TRACE(run.name);
    const auto full = render("occlusion_strength_1.gltf", run.mode, kAmbient, run.device);
    const auto none = render("occlusion_strength_0.gltf", run.mode, kAmbient, run.device);
    EXPECT_GT(halfMean(full, true), 0.05f);  // lit
    EXPECT_LT(maxDifference(full, none), 1e-6f);
  }
}

}  // namespace
}  // namespace voxgi::test
