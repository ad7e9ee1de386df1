// Normal maps (glTF normalTexture, tangent space) in every mode that shades with a
// normal: the quads of tests/data/normal_maps (make_normal_maps.py) are white
// Lambert under a directional light of pi W/m^2 shining straight down, so their
// radiance is the cosine between the shading normal and the light. Their map tilts
// the normal by 45 degrees: raster, rtgi and the path tracer on both devices show
// cos 45 (and the devices agree); with normalTexture.scale 0.5 the closed form of
// the halved tilt; with generated tangents the same as with the file's;
// `--effects -normalmaps` shows the flat quad (1); a map on TEXCOORD_1 reads its
// own coordinates. The back-facing rule
// (normal_map_shared.h): a steep map seen at a grazing angle gives no black pixel
// and no NaN; light from below the surface does not leak through it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/mode_runs.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

constexpr int kSize = 32;

scene::Scene quad(const char* name) {
  return scene::loadGltf(testDataDir() + "/normal_maps/" + name);
}

// The cosine the map's texel gives against a light straight down: the texel the
// generator wrote for a 45-degree tilt towards the tangent, 8-bit, decoded, with
// normalTexture.scale on x and y.
double expectedCosine(double scale) {
  const double t = 45.0 * M_PI / 180.0;
  const double r = std::round((std::sin(t) * 0.5 + 0.5) * 255.0) / 255.0 * 2.0 - 1.0;
  const double g = 128.0 / 255.0 * 2.0 - 1.0;
  const double b = std::round((std::cos(t) * 0.5 + 0.5) * 255.0) / 255.0 * 2.0 - 1.0;
  return b / std::sqrt(r * r * scale * scale + g * g * scale * scale + b * b);
}

std::vector<float> renderImage(const scene::Scene& s, const ModeRun& run,
                               const std::string& effects = "") {
  render::RenderSettings rs;
  rs.width = rs.height = kSize;
  rs.voxels = 64;
  rs.spp = 16;
  rs.effects = effects;
  return renderRun(s, run, rs, scene::Effect::kNormalMaps);
}

// Mean red over the middle half of the image (the quad covers all of it).
double centreMean(const std::vector<float>& px) {
  double sum = 0.0;
  int n = 0;
  for (int y = kSize / 4; y < 3 * kSize / 4; ++y)
    for (int x = kSize / 4; x < 3 * kSize / 4; ++x, ++n)
      sum += px[(static_cast<size_t>(y) * kSize + static_cast<size_t>(x)) * 4];
  return sum / n;
}

class NormalMapsTest : public GlTest {};

TEST_F(NormalMapsTest, TiltedNormalGivesItsCosine) {
  struct Case {
    const char* file;
    double expected;
  };
  const Case cases[] = {{"tilted_quad.gltf", expectedCosine(1.0)},
                        {"tilted_quad_scale.gltf", expectedCosine(0.5)},
                        {"tilted_quad_generated.gltf", expectedCosine(1.0)},
                        {"mirrored_quad.gltf", expectedCosine(1.0)}};
  for (const Case& c : cases) {
    const scene::Scene s = quad(c.file);
    ASSERT_TRUE(s.hasNormalMaps()) << c.file;
    double pathtraced[2] = {0.0, 0.0};
    for (const ModeRun& run : kEveryMode) {
      const double mean = centreMean(renderImage(s, run));
      std::printf("%s, %s: %.4f (closed form %.4f)\n", c.file, run.name, mean, c.expected);
      EXPECT_NEAR(mean, c.expected, 0.02 * c.expected) << c.file << ", " << run.name;
      if (run.mode == render::Mode::kPathtrace)
        pathtraced[run.device == render::PathtraceDevice::kGl ? 0 : 1] = mean;
    }
    EXPECT_NEAR(pathtraced[0], pathtraced[1], 0.01 * pathtraced[1]) << c.file;
  }
}

TEST_F(NormalMapsTest, EffectOffShowsTheFlatQuad) {
  const scene::Scene s = quad("tilted_quad.gltf");
  for (const ModeRun& run : kEveryMode) {
    const double mean = centreMean(renderImage(s, run, "-normalmaps"));
    std::printf("-normalmaps, %s: %.4f\n", run.name, mean);
    EXPECT_NEAR(mean, 1.0, 0.02) << run.name;
  }
}

// Mean red over image columns [x0, x1), middle half of the rows.
double columnsMean(const std::vector<float>& px, int x0, int x1) {
  double sum = 0.0;
  int n = 0;
  for (int y = kSize / 4; y < 3 * kSize / 4; ++y)
    for (int x = x0; x < x1; ++x, ++n)
      sum += px[(static_cast<size_t>(y) * kSize + static_cast<size_t>(x)) * 4];
  return sum / n;
}

// A normal map on TEXCOORD_1 while another texture reads TEXCOORD_0: it reads its
// own channel, where the map's tilted half lies on the left of the image (through
// TEXCOORD_0 it would lie on the right), with tangents generated from that channel.
TEST_F(NormalMapsTest, ReadsItsOwnTextureCoordinates) {
  const scene::Scene s = quad("channel1_quad.gltf");
  ASSERT_TRUE(s.hasNormalMaps());
  ASSERT_EQ(s.materials[0].normalChannel, 1);
  for (const ModeRun& run : kEveryMode) {
    const std::vector<float> px = renderImage(s, run);
    // Columns well inside each half's two texels (the quad nearly fills the image).
    const double left = columnsMean(px, 5, 11), right = columnsMean(px, 21, 27);
    std::printf("channel1_quad.gltf, %s: left %.4f (closed form %.4f), right %.4f (flat 1)\n",
                run.name, left, expectedCosine(1.0), right);
    EXPECT_NEAR(left, expectedCosine(1.0), 0.02 * expectedCosine(1.0)) << run.name;
    EXPECT_NEAR(right, 1.0, 0.02) << run.name;
  }
}

// The grazing view of an 80-degree map: the mapped normal faces away from the
// camera. Wherever the flat quad is lit, the mapped one is lit too (no black
// pixels), and nothing is NaN or infinite.
TEST_F(NormalMapsTest, GrazingSteepMapNoBlackNoNan) {
  const scene::Scene s = quad("grazing_quad.gltf");
  for (const ModeRun& run : kEveryMode) {
    const auto flat = renderImage(s, run, "-normalmaps");
    const auto mapped = renderImage(s, run);
    int covered = 0, black = 0, bad = 0;
    for (size_t i = 0; i < mapped.size(); i += 4) {
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(mapped[i + static_cast<size_t>(k)])) ++bad;
      if (flat[i] > 0.5f) {
        ++covered;
        if (!(mapped[i] > 0.02f)) ++black;
      }
    }
    std::printf("grazing, %s: %d pixels of the quad, %d black, %d not finite\n", run.name, covered,
                black, bad);
    EXPECT_GT(covered, kSize);
    EXPECT_EQ(black, 0) << run.name;
    EXPECT_EQ(bad, 0) << run.name;
  }
}

// Light from 18 degrees below the quad, which the 80-degree map's normal faces:
// the surface does not, so no light reaches the camera's side.
TEST_F(NormalMapsTest, NoLightThroughTheSurface) {
  const scene::Scene s = quad("leak_quad.gltf");
  for (const ModeRun& run : kEveryMode) {
    const auto px = renderImage(s, run);
    double peak = 0.0;
    for (size_t i = 0; i < px.size(); i += 4)
      for (int k = 0; k < 3; ++k) peak = std::max(peak, double(px[i + static_cast<size_t>(k)]));
    std::printf("light from below, %s: brightest %.5f\n", run.name, peak);
    EXPECT_LT(peak, 1e-3) << run.name;
  }
}

}  // namespace
}  // namespace voxgi::test
