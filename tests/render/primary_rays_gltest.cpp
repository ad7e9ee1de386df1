// rtgi's G-buffer made by rays (RtgiPass::Settings::Primary::kRays,
// rtgi_gbuffer.comp) against the rasterized one: the same surfaces, the same
// normals, the same image. The material channels (textures, samplers, texture
// coordinates, vertex colours, normal maps) are checked in every mode by the tests
// that run kEveryMode, which has a row for primary rays; these check what only
// primary visibility does: back faces culled where the material is single-sided,
// normals turned towards the viewer where it is double-sided, emission, the
// background, and the choice kAuto makes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "core/log.h"
#include "render/renderer.h"
#include "support/gl_fixture.h"
#include "support/scene_builder.h"

namespace voxgi::test {
namespace {

using Primary = render::RtgiPass::Settings::Primary;
constexpr int kSize = 96;

// A grey single-sided wall facing +z, lit head-on by a directional light, seen from
// 4 m. Before it, at z = 1: on the left a single-sided white quad facing the wall
// (the raster culls it: the wall shows through), on the right a double-sided white
// quad facing the wall (shown from behind, its normal turned to the viewer: lit),
// and below the middle an emitting single-sided quad facing the camera. Around the
// wall, the background.
scene::Scene facesScene() {
  SceneBuilder b;
  const int grey = b.addMaterial(glm::vec3(0.5f), glm::vec3(0.0f), false);
  const int oneSided = b.addMaterial(glm::vec3(0.9f), glm::vec3(0.0f), false);
  const int twoSided = b.addMaterial(glm::vec3(0.9f), glm::vec3(0.0f), true);
  const int glowing = b.addMaterial(glm::vec3(0.2f), glm::vec3(2.0f, 1.0f, 0.5f), false);
  // A quad in the plane z, x in [x0, x1], y in [y0, y1], facing +z or (back) -z.
  auto quad = [&](float x0, float x1, float y0, float y1, float z, bool back, int material) {
    std::vector<glm::vec3> c = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z},
                                {x0, y0, z}, {x1, y1, z}, {x0, y1, z}};
    if (back) {
      std::swap(c[1], c[2]);
      std::swap(c[4], c[5]);
    }
    b.addTriangles(c, material);
  };
  quad(-1.6f, 1.6f, -1.2f, 1.2f, 0.0f, false, grey);
  quad(-1.3f, -0.3f, -0.2f, 0.8f, 1.0f, true, oneSided);
  quad(0.3f, 1.3f, -0.2f, 0.8f, 1.0f, true, twoSided);
  quad(-0.4f, 0.4f, -1.0f, -0.5f, 1.0f, false, glowing);
  scene::Scene s = b.finish();
  lightHeadOnFromZ(&s, 4.0f);
  s.camera.fromFile = true;
  return s;
}

class PrimaryRaysTest : public GlProgramsTest {
 protected:
  // One rtgi frame at the pixel centres, direct light only (the same light every
  // frame, so the two G-buffers give the same image where they agree).
  std::vector<float> render(const scene::Scene& s, Primary primary, bool* rays) {
    render::RenderSettings rs;
    rs.width = rs.height = kSize;
    rs.voxels = 32;
    rs.jitter = false;
    rs.effects = "-indirect,-specular";
    rs.rtgi.primary = primary;
    render::Renderer r(*programs_, s, rs);
    r.renderFrame();
    *rays = r.rtgi()->primaryRays();
    return r.readLinear();
  }
};

TEST_F(PrimaryRaysTest, RaysShowWhatTheRasterShows) {
  const scene::Scene s = facesScene();
  bool rasterRays = true, castRays = false;
  const std::vector<float> raster = render(s, Primary::kRaster, &rasterRays);
  const std::vector<float> rays = render(s, Primary::kRays, &castRays);
  EXPECT_FALSE(rasterRays);
  EXPECT_TRUE(castRays);
  // Pixels whose colour differs by more than 1% of the brightest channel value.
  float peak = 0.0f;
  for (float v : raster) peak = std::max(peak, v);
  int differing = 0, lit = 0, background = 0;
  for (size_t i = 0; i < raster.size(); i += 4) {
    float d = 0.0f, sum = 0.0f;
    for (size_t c = 0; c < 3; ++c) {
      d = std::max(d, std::abs(raster[i + c] - rays[i + c]));
      sum += raster[i + c];
    }
    differing += d > 0.01f * peak ? 1 : 0;
    lit += sum > 0.0f ? 1 : 0;
    background += sum == 0.0f ? 1 : 0;
  }
  std::printf("%d of %d pixels differ by more than 1%%; %d lit, %d background\n", differing,
              kSize * kSize, lit, background);
  EXPECT_GT(background, kSize * kSize / 10);  // the wall does not fill the view
  EXPECT_GT(lit, kSize * kSize / 2);
  EXPECT_EQ(differing, 0);
}

TEST_F(PrimaryRaysTest, AutoCastsRaysOnlyWhereRasterizingCostsMore) {
  using render::resolvePrimary;
  // Software GL, more than 4 triangles a pixel, static meshes: rays.
  EXPECT_EQ(resolvePrimary(Primary::kAuto, true, 400001, 100000, false), Primary::kRays);
  EXPECT_EQ(resolvePrimary(Primary::kAuto, true, 399999, 100000, false), Primary::kRaster);
  // A hardware rasterizer, or meshes that move (no BVH): the raster.
  EXPECT_EQ(resolvePrimary(Primary::kAuto, false, 10000000, 100000, false), Primary::kRaster);
  EXPECT_EQ(resolvePrimary(Primary::kAuto, true, 10000000, 100000, true), Primary::kRaster);
  // An explicit choice stands, except rays where meshes move.
  EXPECT_EQ(resolvePrimary(Primary::kRays, false, 10, 100000, false), Primary::kRays);
  EXPECT_EQ(resolvePrimary(Primary::kRaster, true, 10000000, 100000, false), Primary::kRaster);
  EXPECT_THROW(resolvePrimary(Primary::kRays, true, 10, 100000, true), Error);
}

}  // namespace
}  // namespace voxgi::test
