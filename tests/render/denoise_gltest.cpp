// rtgi's denoiser (RtgiPass::Settings::denoise, shaders/include/rtgi_denoise.glsl):
// after two frames it takes most of the noise out of the image, without blurring away
// what the converged image and the path tracer show: texture detail, the contact
// shadow at a box's foot, mirror reflections (which it leaves as they are); as frames
// accumulate it fades out, and it stays finite through camera moves, interleaving
// and sparse starts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "image/metrics.h"
#include "render/renderer.h"
#include "support/gl_fixture.h"
#include "support/scene_builder.h"

namespace voxgi::test {
namespace {

constexpr int kSize = 96;

// The 0.6-unit box on the floor of both scenes: x and z in [-kBoxHalf, kBoxHalf],
// y in [0, 2 kBoxHalf], five faces (no bottom).
constexpr float kBoxHalf = 0.3f;
void addBox(scene::Scene* s, int material) {
  const float h = kBoxHalf, top = 2.0f * kBoxHalf;
  addQuad(s, material, {{-h, 0, h}, {h, 0, h}, {h, top, h}, {-h, top, h}});        // front
  addQuad(s, material, {{h, 0, h}, {h, 0, -h}, {h, top, -h}, {h, top, h}});        // right
  addQuad(s, material, {{-h, 0, -h}, {-h, 0, h}, {-h, top, h}, {-h, top, -h}});    // left
  addQuad(s, material, {{h, 0, -h}, {-h, 0, -h}, {-h, top, -h}, {h, top, -h}});    // back
  addQuad(s, material, {{-h, top, h}, {h, top, h}, {h, top, -h}, {-h, top, -h}});  // top
}

// A 4 x 4 floor (y = 0) whose base colour is a 16 x 16 checker texture (white 0.8,
// grey 0.2, nearest: 0.25-unit squares), a white back wall at z = -1.6 with a mirror
// panel (metallic, roughness 0) in front of its left half, a 0.6-unit white box on
// the floor, and a square area light (0.6 units, facing down) 1.4 above the floor to
// the box's right: the box's soft shadow on its left, and one bounce, both noisy
// after a few frames.
scene::Scene checkerRoom() {
  scene::Scene s;
  s.path = "checker_room";
  scene::Material floor, white, mirror, lamp;
  floor.baseColor = glm::vec4(1.0f);
  floor.metallic = 0.0f;
  floor.baseColorTexture = 0;
  white.baseColor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  white.metallic = 0.0f;
  mirror.baseColor = glm::vec4(0.9f, 0.9f, 0.9f, 1.0f);
  mirror.metallic = 1.0f;
  mirror.roughness = 0.0f;
  lamp.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  lamp.metallic = 0.0f;
  lamp.emission = glm::vec3(12.0f);
  s.materials = {floor, white, mirror, lamp};
  scene::Texture t;
  t.width = t.height = 16;
  t.srgb = false;
  t.magFilter = scene::kFilterNearest;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const uint8_t v = (x + y) % 2 == 0 ? 204 : 51;
      t.rgba8.insert(t.rgba8.end(), {v, v, v, 255});
    }
  s.textures.push_back(t);
  addQuad(&s, 0, {{-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, {-2, 0, -2}},
          {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  addQuad(&s, 1, {{-2, 0, -1.6f}, {2, 0, -1.6f}, {2, 2.2f, -1.6f}, {-2, 2.2f, -1.6f}});
  addQuad(
      &s, 2,
      {{-1.8f, 0.2f, -1.55f}, {-0.4f, 0.2f, -1.55f}, {-0.4f, 1.6f, -1.55f}, {-1.8f, 1.6f, -1.55f}});
  addBox(&s, 1);
  // The lamp, facing down, to the box's right: the box's shadow falls to its left.
  const float h = kBoxHalf;
  addQuad(&s, 3,
          {{1.0f - h, 1.4f, -h}, {1.0f + h, 1.4f, -h}, {1.0f + h, 1.4f, h}, {1.0f - h, 1.4f, h}});
  s.camera.position = glm::vec3(0.0f, 1.5f, 2.8f);
  s.camera.forward = glm::normalize(glm::vec3(0.0f, 0.2f, -0.2f) - s.camera.position);
  s.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  s.camera.yfov = 0.9f;
  s.camera.fromFile = true;
  s.finalize();
  return s;
}

// The box of checkerRoom on a plain white floor before a white back wall, lit by a
// point light 1.5 above the floor to its right: the box's shadow is hard, with its
// far edge on the floor at x = -1.3 (the box's top edge, x = -0.3 at height 0.6,
// projected from the light at x = 1.2), and the light the walls and box bounce into
// it is noisy after a few frames. The direct light of a point is the same every
// frame (the pixel centres are sampled): only the bounce is noise.
scene::Scene pointLitBox() {
  scene::Scene s;
  s.path = "point_lit_box";
  scene::Material white;
  white.baseColor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  white.metallic = 0.0f;
  s.materials = {white};
  addQuad(&s, 0, {{-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, {-2, 0, -2}});
  addQuad(&s, 0, {{-2, 0, -1.6f}, {2, 0, -1.6f}, {2, 2.2f, -1.6f}, {-2, 2.2f, -1.6f}});
  addBox(&s, 0);
  scene::Light light;
  light.type = scene::LightType::kPoint;
  light.position = glm::vec3(1.2f, 1.5f, 0.0f);
  light.intensity = 6.0f;
  s.lights.push_back(light);
  s.camera.position = glm::vec3(0.0f, 1.5f, 2.8f);
  s.camera.forward = glm::normalize(glm::vec3(-0.3f, 0.2f, -0.2f) - s.camera.position);
  s.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  s.camera.yfov = 0.9f;
  s.camera.fromFile = true;
  s.finalize();
  return s;
}

// The pixel (column, row from the top) where world point p lands.
glm::ivec2 project(const scene::Scene& s, glm::vec3 p) {
  const glm::vec4 c = s.camera.projection(1.0f) * s.camera.view() * glm::vec4(p, 1.0f);
  const glm::vec2 ndc = glm::vec2(c) / c.w;
  return {static_cast<int>((ndc.x * 0.5f + 0.5f) * kSize),
          static_cast<int>((0.5f - ndc.y * 0.5f) * kSize)};
}

image::Image toImage(const std::vector<float>& rgba) {
  image::Image im;
  im.width = im.height = kSize;
  im.channels = 3;
  for (size_t i = 0; i < rgba.size(); i += 4)
    im.pixels.insert(im.pixels.end(), {rgba[i], rgba[i + 1], rgba[i + 2]});
  return im;
}

// Mean luminance over the (2r + 1)^2 pixels about `at`.
double windowMean(const image::Image& im, glm::ivec2 at, int r) {
  EXPECT_TRUE(at.x >= r && at.y >= r && at.x + r < kSize && at.y + r < kSize);
  const std::vector<double> l = image::luminance(im);
  double sum = 0.0;
  for (int y = at.y - r; y <= at.y + r; ++y)
    for (int x = at.x - r; x <= at.x + r; ++x) sum += l[static_cast<size_t>(y * kSize + x)];
  return sum / ((2 * r + 1) * (2 * r + 1));
}

// Mean absolute luminance step between horizontal and vertical neighbours over the
// window about `at`: the checker's edges, and noise.
double windowGradient(const image::Image& im, glm::ivec2 at, int r) {
  const std::vector<double> l = image::luminance(im);
  double sum = 0.0;
  for (int y = at.y - r; y < at.y + r; ++y)
    for (int x = at.x - r; x < at.x + r; ++x) {
      const auto i = static_cast<size_t>(y * kSize + x);
      sum += std::abs(l[i + 1] - l[i]) + std::abs(l[i + kSize] - l[i]);
    }
  return sum / (4.0 * r * r);
}

class DenoiseTest : public GlProgramsTest {
 protected:
  // kSize x kSize, 64³ voxels, in `mode`.
  static render::RenderSettings baseSettings(render::Mode mode) {
    render::RenderSettings rs;
    rs.mode = mode;
    rs.width = rs.height = kSize;
    rs.voxels = 64;
    return rs;
  }

  image::Image render(const scene::Scene& s, render::Mode mode, int frames, bool denoise,
                      uint32_t seed) {
    render::RenderSettings rs = baseSettings(mode);
    rs.rtgi.seed = seed;
    rs.rtgi.denoise = denoise;
    // Every frame samples the pixel centres: what two frames lack against 64 is then
    // noise alone, not antialiasing too.
    rs.jitter = false;
    rs.octree.seed = seed;
    rs.spp = 256;
    rs.pathtrace.seed = seed;
    render::Renderer r(*programs_, s, rs);
    for (int f = 0; f < frames; ++f) r.renderFrame();
    return toImage(r.readLinear());
  }
};

TEST_F(DenoiseTest, TakesOutTheNoiseOfTwoFramesAndKeepsWhatTheImageShows) {
  const scene::Scene s = checkerRoom();
  const image::Image converged = render(s, render::Mode::kRtgi, 64, false, 1);
  const image::Image raw = render(s, render::Mode::kRtgi, 2, false, 2);
  const image::Image denoised = render(s, render::Mode::kRtgi, 2, true, 2);
  const image::Image pt = render(s, render::Mode::kPathtrace, 1, false, 3);

  const double rawError = image::errorMetrics(raw, converged).rmse;
  const double denoisedError = image::errorMetrics(denoised, converged).rmse;
  // The checker where the floor is lit and open (in front of the box, to its right).
  const glm::ivec2 open = project(s, {0.9f, 0.0f, 0.9f});
  // The box's shadow at its foot, and the lit floor beyond the shadow.
  const glm::ivec2 foot = project(s, {-0.45f, 0.0f, 0.1f});
  const glm::ivec2 away = project(s, {-0.6f, 0.0f, 1.1f});
  // The mirror panel's middle: the floor and room reflected.
  const glm::ivec2 mirror = project(s, {-1.1f, 0.9f, -1.55f});
  const auto contact = [&](const image::Image& im) {
    return windowMean(im, foot, 2) / windowMean(im, away, 2);
  };
  std::printf(
      "rmse against 64 frames: 2 frames %.4f, denoised %.4f; checker gradient: converged "
      "%.4f, denoised %.4f, 2 frames %.4f, path tracer %.4f; contact shadow (foot / open "
      "floor): converged %.3f, denoised %.3f, path tracer %.3f\n",
      rawError, denoisedError, windowGradient(converged, open, 5),
      windowGradient(denoised, open, 5), windowGradient(raw, open, 5), windowGradient(pt, open, 5),
      contact(converged), contact(denoised), contact(pt));

  // Most of the noise is gone.
  EXPECT_LT(denoisedError, 0.6 * rawError);
  // The checker's edges stay as sharp as converged (the noise of two frames would
  // add to the gradient; blurring would take from it).
  EXPECT_NEAR(windowGradient(denoised, open, 5) / windowGradient(converged, open, 5), 1.0, 0.1);
  // The contact shadow keeps its depth, as the converged image and the path tracer
  // show it.
  EXPECT_NEAR(contact(denoised), contact(converged), 0.05);
  EXPECT_NEAR(contact(denoised), contact(pt), 0.1);
  // Mirrors are left as they are: the same samples give the same pixels.
  for (int y = mirror.y - 3; y <= mirror.y + 3; ++y)
    for (int x = mirror.x - 3; x <= mirror.x + 3; ++x)
      for (int c = 0; c < 3; ++c) {
        const auto i = static_cast<size_t>((y * kSize + x) * 3 + c);
        ASSERT_EQ(denoised.pixels[i], raw.pixels[i]) << "mirror pixel " << x << "," << y;
      }
}

// After one frame a pixel's own moments say nothing of its noise (one sample has no
// variance): the filter takes it from the moments of the 7x7 pixels around it on its
// surface, summed along the rows and then down the columns. Without them it would
// leave the first frame, the image most of a camera move shows, as noisy as it came.
TEST_F(DenoiseTest, TakesOutTheNoiseOfTheFirstFrame) {
  const scene::Scene s = checkerRoom();
  const image::Image converged = render(s, render::Mode::kRtgi, 64, false, 1);
  double ratio = 0.0;
  for (uint32_t seed : {2u, 3u}) {
    const image::Image raw = render(s, render::Mode::kRtgi, 1, false, seed);
    const image::Image denoised = render(s, render::Mode::kRtgi, 1, true, seed);
    const double rawError = image::errorMetrics(raw, converged).rmse;
    const double denoisedError = image::errorMetrics(denoised, converged).rmse;
    std::printf("seed %u: rmse against 64 frames: 1 frame %.4f, denoised %.4f\n", seed, rawError,
                denoisedError);
    ratio = std::max(ratio, denoisedError / rawError);
  }
  // Measured 0.25 on both seeds; 1.0 with the neighbours left out.
  EXPECT_LT(ratio, 0.35);
}

// The filter takes the direct light and the rest apart, each against its own noise:
// a point light's hard shadow, exact in every frame, keeps its edge while the noisy
// light bounced into the shadow is smoothed. Filtered as one, the bounce's noise
// would let the luminance stop blur the edge.
TEST_F(DenoiseTest, KeepsAHardShadowsEdgeWhileSmoothingTheBounce) {
  const scene::Scene s = pointLitBox();
  const image::Image converged = render(s, render::Mode::kRtgi, 64, false, 1);
  const image::Image raw = render(s, render::Mode::kRtgi, 2, false, 2);
  const image::Image denoised = render(s, render::Mode::kRtgi, 2, true, 2);
  // Pixels just inside and just outside the shadow's far edge (x = -1.3), and the
  // bounce deep in the shadow.
  const glm::ivec2 inside = project(s, {-1.2f, 0.0f, 0.2f});
  const glm::ivec2 outside = project(s, {-1.4f, 0.0f, 0.2f});
  const glm::ivec2 shade = project(s, {-0.8f, 0.0f, 0.1f});
  const auto edge = [&](const image::Image& im) {
    return windowMean(im, inside, 1) / windowMean(im, outside, 1);
  };
  const double rawNoise = windowGradient(raw, shade, 4);
  const double denoisedNoise = windowGradient(denoised, shade, 4);
  std::printf(
      "shadow edge (inside / outside pixel): converged %.4f, 2 frames %.4f, denoised %.4f; "
      "gradient in the shade: converged %.5f, 2 frames %.5f, denoised %.5f\n",
      edge(converged), edge(raw), edge(denoised), windowGradient(converged, shade, 4), rawNoise,
      denoisedNoise);
  // The bounce in the shadow is smoothed...
  EXPECT_LT(denoisedNoise, 0.5 * rawNoise);
  // ...and the shadow's edge stays as sharp as converged.
  EXPECT_NEAR(edge(denoised), edge(converged), 0.05);
}

// As a still image converges, the noise the filter measures falls as 1/n and so does
// what it changes: after 64 frames the denoised image is the running mean, within
// what remains of its noise.
TEST_F(DenoiseTest, FadesOutAsTheImageConverges) {
  const scene::Scene s = checkerRoom();
  const image::Image mean = render(s, render::Mode::kRtgi, 64, false, 1);
  const image::Image denoised = render(s, render::Mode::kRtgi, 64, true, 1);
  const image::Image other = render(s, render::Mode::kRtgi, 64, false, 2);
  const double change = image::errorMetrics(denoised, mean).rmse;
  const double noise = image::errorMetrics(other, mean).rmse;  // two seeds' difference
  std::printf("64 frames: denoised against the mean %.5f, a second seed's mean %.5f\n", change,
              noise);
  EXPECT_LT(change, noise);
  EXPECT_GT(change, 0.0);  // it does filter
}

// The viewer's `n` key: turned on in a running renderer, the denoiser makes its
// images then (a pass that never denoises has none) and filters from the restart it
// causes, as a renderer made with it on does; turned off, the image is the mean.
TEST_F(DenoiseTest, TurnsOnAndOffInARunningRenderer) {
  const scene::Scene s = checkerRoom();
  render::RenderSettings rs = baseSettings(render::Mode::kRtgi);
  rs.jitter = false;
  const image::Image fresh = render(s, render::Mode::kRtgi, 2, true, rs.rtgi.seed);
  const image::Image raw = render(s, render::Mode::kRtgi, 2, false, rs.rtgi.seed);
  render::Renderer r(*programs_, s, rs);
  for (int f = 0; f < 3; ++f) r.renderFrame();
  const size_t bytesOff = r.targetBytes();
  r.setDenoise(true);
  for (int f = 0; f < 2; ++f) r.renderFrame();
  const image::Image on = toImage(r.readLinear());
  EXPECT_GT(r.targetBytes(), bytesOff);
  const double toFresh = image::errorMetrics(on, fresh).rmse;
  const double rawToFresh = image::errorMetrics(raw, fresh).rmse;
  std::printf("turned on: rmse against a renderer made with it on %.5f (the raw mean's %.5f)\n",
              toFresh, rawToFresh);
  EXPECT_LT(toFresh, 0.5 * rawToFresh);
  r.setDenoise(false);
  for (int f = 0; f < 2; ++f) r.renderFrame();
  EXPECT_LT(image::errorMetrics(toImage(r.readLinear()), raw).rmse, 0.5 * rawToFresh);
}

// Camera moves (reprojected history, disocclusions), an interleave with a sparse
// start (pixels with no sample yet): every pixel shown stays finite.
TEST_F(DenoiseTest, StaysFiniteThroughMovesAndSparseStarts) {
  const scene::Scene s = checkerRoom();
  render::RenderSettings rs = baseSettings(render::Mode::kRtgi);
  rs.rtgi.denoise = true;
  rs.rtgi.interleave = 4;
  rs.rtgi.sparseStart = true;
  render::Renderer r(*programs_, s, rs);
  scene::Camera c = s.camera;
  for (int f = 0; f < 12; ++f) {
    if (f % 3 == 2) c.position += glm::vec3(0.15f, 0.0f, 0.0f);
    r.renderFrame(c);
    const std::vector<float> px = r.readLinear();
    double sum = 0.0;
    for (size_t i = 0; i < px.size(); i += 4)
      for (size_t k = 0; k < 3; ++k) {
        ASSERT_TRUE(std::isfinite(px[i + k])) << "frame " << f << " pixel " << i / 4;
        sum += px[i + k];
      }
    EXPECT_GT(sum, 0.0) << "frame " << f;
  }
}

// The filter moves light between pixels without making or losing any: the denoised
// image holds the light of the running mean it filters, where the noise is of rare
// bright samples (a small lamp's light bounced into the box's shadow, its soft
// shadow) that a normalised average weighs against (rtgi_denoise.comp, filterTerm).
TEST_F(DenoiseTest, KeepsTheImagesLight) {
  const scene::Scene s = checkerRoom();
  double worst = 0.0;
  for (uint32_t seed : {1u, 2u})
    for (int frames : {1, 2}) {
      const double ratio = image::errorMetrics(render(s, render::Mode::kRtgi, frames, true, seed),
                                               render(s, render::Mode::kRtgi, frames, false, seed))
                               .meanLuminanceRatio;
      worst = std::max(worst, std::abs(ratio - 1.0));
    }
  // Measured over seeds 1-2 and 1-2 frames: 0.02-0.08%; a normalised average (SVGF's),
  // 1.5-3.9% darker.
  EXPECT_LT(worst, 0.005);
}

}  // namespace
}  // namespace voxgi::test
