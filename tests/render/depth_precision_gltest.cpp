// Depth precision at architectural scale: a camera inside a 27 m scene gets a near
// plane of 1e-5 of its far one (scene::fitClipPlanes), and a 15 cm wall 23 m away
// must still hide what touches its back. With the usual depth mapping the float
// depth buffer resolved only about two steps across the wall there, and the sealed
// room behind the validation set's hall showed through its wall as black lines along
// its edges; reversed depth (scene::Camera::projection, render::beginOpaquePass)
// resolves well under a millimetre.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

constexpr int kSize = 256;

// The validation set's night hall (tools/make-hall): its camera is inside the
// 27 m scene, 23 m from the hall's 15 cm east wall, behind which the sealed room's
// walls and roof touch the wall's back face. Without `hidden`, every triangle wholly
// behind the wall's front face (the sealed room, the wall's back face) is made
// degenerate, so it draws nothing and blocks no ray.
scene::Scene hall(bool hidden) {
  scene::Scene s = scene::loadGltf(sourceDir() + "/scenes/hall/hall_night.gltf");
  if (!hidden) {
    const double behind = 12.0 + 1e-3;  // the wall's front face is at x = 12
    for (size_t t = 0; t + 2 < s.indices.size(); t += 3) {
      bool all = true;
      for (size_t k = 0; k < 3; ++k)
        all = all && s.vertices[s.indices[t + k]].position.x + s.origin.x > behind;
      if (all) s.indices[t + 1] = s.indices[t + 2] = s.indices[t];
    }
  }
  return s;
}

std::vector<float> render(const scene::Scene& s, render::Mode mode) {
  render::RenderSettings rs;
  rs.mode = mode;
  rs.width = rs.height = kSize;
  rs.voxels = 64;
  rs.jitter = false;
  // rtgi: direct light only, from the hall's point lights and moon, each with its
  // shadow ray (no random draw), which nothing behind the wall can reach.
  rs.effects = "-indirect,-specular";
  rs.rtgi.exactLights = 64;
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::Renderer r(programs, s, rs);
  r.renderFrame();
  return r.readLinear();
}

class DepthPrecisionTest : public GlTest, public testing::WithParamInterface<render::Mode> {};

INSTANTIATE_TEST_SUITE_P(Modes, DepthPrecisionTest,
                         testing::Values(render::Mode::kRaster, render::Mode::kRtgi),
                         [](const auto& p) { return std::string(render::modeName(p.param)); });

// The image is the same with the sealed room behind the wall as without it.
TEST_P(DepthPrecisionTest, AWallHidesWhatTouchesItsBackAt23Metres) {
  const scene::Scene with = hall(true);
  ASSERT_LT(with.camera.znear, 1e-3f) << "the camera must be inside the scene's bounds";
  const std::vector<float> a = render(with, GetParam());
  const std::vector<float> b = render(hall(false), GetParam());
  ASSERT_EQ(a.size(), b.size());
  int differ = 0, lit = 0;
  for (size_t i = 0; i < a.size(); i += 4) {
    float d = 0.0f;
    for (size_t c = 0; c < 3; ++c) d = std::max(d, std::abs(a[i + c] - b[i + c]));
    if (d > 1e-3f * std::max(1.0f, b[i + 1])) ++differ;
    if (b[i + 1] > 1e-3f) ++lit;
  }
  EXPECT_EQ(differ, 0) << "pixels that show the sealed room through the wall";
  EXPECT_GT(lit, kSize * kSize / 2) << "the hall is lit and in view";
}

}  // namespace
}  // namespace voxgi::test
