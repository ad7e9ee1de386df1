// The two modes that show the voxels themselves, checked against what they must
// draw rather than against themselves: `points` (every occupied voxel as a cube,
// albedo under its fixed inspection light) and `dvr` (the lit octree, composited
// front to back). A pass that draws nothing, draws in the wrong place, or loses the
// light or the emission fails these.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "render/renderer.h"
#include "support/gl_fixture.h"
#include "support/scene_builder.h"

namespace voxgi::test {
namespace {

constexpr int kSize = 64;

class InspectionModesTest : public GlProgramsTest {
 protected:
  // A unit box at the origin seen straight on from (0, 0, 3): its front face
  // (z = 0.5, normal +z) fills the middle of the image.
  static scene::Scene box(glm::vec3 albedo, glm::vec3 emission) {
    SceneBuilder b;
    b.addBox(glm::vec3(-0.5f), glm::vec3(0.5f), b.addMaterial(albedo, emission));
    scene::Scene s = b.finish();
    s.camera = scene::Camera{};  // at (0, 0, 3), looking down -z, 40 degrees
    s.camera.fromFile = true;
    return s;
  }

  std::vector<float> render(const scene::Scene& s, render::Mode mode) {
    render::RenderSettings rs;
    rs.mode = mode;
    rs.width = rs.height = kSize;
    rs.voxels = 32;
    render::Renderer r(*programs_, s, rs);
    r.renderFrame();
    return r.readLinear();
  }

  // Pixel (x, y) of a linear RGBA image, rows bottom first.
  static glm::vec3 at(const std::vector<float>& px, int x, int y) {
    const size_t i = 4 * (static_cast<size_t>(y) * kSize + static_cast<size_t>(x));
    return {px[i], px[i + 1], px[i + 2]};
  }

  // The front face's half-width in pixels: 0.5 at distance 2.5, 40-degree field.
  static double faceHalfWidthPx() { return 0.5 / 2.5 / std::tan(0.5 * 0.6981317) * kSize / 2; }

  // Pixels whose centre lies within `inner` x the face's half-width of the image
  // centre, and those beyond `outer` x it (Chebyshev distance: the face is square).
  static void countCovered(const std::vector<float>& px, double inner, double outer,
                           int* insideDark, int* outsideLit) {
    *insideDark = *outsideLit = 0;
    const double h = faceHalfWidthPx();
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const double d = std::max(std::abs(x + 0.5 - kSize / 2.0), std::abs(y + 0.5 - kSize / 2.0));
        const glm::vec3 c = at(px, x, y);
        const bool lit = c.r + c.g + c.b > 1e-3f;
        if (d < inner * h && !lit) ++*insideDark;
        if (d > outer * h && lit) ++*outsideLit;
      }
  }
};

// points: the cubes cover the box's silhouette, give or take a voxel, and nothing
// else; a cube face seen head on shows the albedo under the inspection light
// (0.15 + 0.425 head light + 0.425 x the key light's z, 0.4969): 0.786 x albedo.
TEST_F(InspectionModesTest, PointsDrawTheVoxelsWhereTheBoxIsInItsAlbedo) {
  const glm::vec3 albedo(0.8f, 0.4f, 0.1f);
  const std::vector<float> px = render(box(albedo, glm::vec3(0.0f)), render::Mode::kPoints);
  int insideDark = 0, outsideLit = 0;
  // A voxel is 1/32 of the grid (about 1.2 units wide here): up to a voxel's
  // projected width (15% of the face's half-width) either way.
  countCovered(px, 0.85, 1.2, &insideDark, &outsideLit);
  EXPECT_EQ(insideDark, 0);
  EXPECT_EQ(outsideLit, 0);
  const double light = 0.15 + 0.425 + 0.425 * 0.5 / std::sqrt(1.0125);
  const glm::vec3 c = at(px, kSize / 2, kSize / 2);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], albedo[k] * light, 0.01) << "channel " << k;
}

// dvr: an emitting box alone (no light, so no default one either) shows its
// emission, composited over opaque voxels, where the box is and nowhere else.
TEST_F(InspectionModesTest, DvrShowsAnEmittersRadianceWhereItIs) {
  const glm::vec3 emission(2.0f, 1.0f, 0.5f);
  const std::vector<float> px = render(box(glm::vec3(0.5f), emission), render::Mode::kDvr);
  int insideDark = 0, outsideLit = 0;
  countCovered(px, 0.85, 1.2, &insideDark, &outsideLit);
  EXPECT_EQ(insideDark, 0);
  EXPECT_EQ(outsideLit, 0);
  const glm::vec3 c = at(px, kSize / 2, kSize / 2);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], emission[k], 0.01 * emission[k]) << "channel " << k;
}

// dvr: a box lit head on by a point light at the camera shows the light its front
// voxels hold, which is the light the raster baseline computes on the surface
// (unshadowed direct light: albedo / pi x I / d^2 at the face's centre). Measured:
// dvr / raster 0.994, 1.001, 0.997 (the voxels' light is taken at their centres).
// The light at the eye is also the case where the half vector equals the view
// (schlickFresnel's cosine a rounding above 1), which once made the raster NaN.
TEST_F(InspectionModesTest, DvrShowsTheDirectLightTheRasterComputes) {
  scene::Scene s = box(glm::vec3(0.6f, 0.5f, 0.4f), glm::vec3(0.0f));
  scene::Light light;
  light.position = glm::vec3(0.0f, 0.0f, 3.0f);
  light.intensity = 20.0f;
  s.lights = {light};
  const glm::vec3 dvr = at(render(s, render::Mode::kDvr), kSize / 2, kSize / 2);
  const glm::vec3 raster = at(render(s, render::Mode::kRaster), kSize / 2, kSize / 2);
  std::printf("front face centre: dvr (%.4f %.4f %.4f), raster (%.4f %.4f %.4f)\n", dvr.r, dvr.g,
              dvr.b, raster.r, raster.g, raster.b);
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(raster[k], 0.0f);
    EXPECT_NEAR(dvr[k] / raster[k], 1.0, 0.02) << "channel " << k;
  }
}

}  // namespace
}  // namespace voxgi::test
