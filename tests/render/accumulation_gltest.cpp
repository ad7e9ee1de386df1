// Long progressive accumulation in the path tracer: 10,000 frames of one sample
// per pixel stay finite, keep converging to the closed form, and add up to
// exactly the image of one 10,000-sample frame (no drift from splitting the sum
// over frames). The per-pixel sums are Kahan-compensated float (pathtrace.comp).
//
// Scene: a white furnace, a closed box that emits Le and reflects with albedo a on
// its inside, so every pixel's expectation is the same known value, Le (1 - a^d) /
// (1 - a) for max depth d (Russian roulette is unbiased), and the spread over the
// pixels of one image measures its noise.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "gl/program_cache.h"
#include "render/renderer.h"
#include "support/gl_fixture.h"
#include "support/scene_builder.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

constexpr int kSize = 8;
constexpr float kAlbedo = 0.5f, kLe = 1.0f;
constexpr int kMaxDepth = 8;

scene::Scene furnaceBox() {
  SceneBuilder b;
  const int m = b.addMaterial(glm::vec3(kAlbedo), glm::vec3(kLe));
  b.addBox(glm::vec3(-1.0f), glm::vec3(1.0f), m);
  scene::Scene s = b.finish();
  s.camera.position = glm::vec3(0.1f, -0.2f, 0.3f);
  s.camera.forward = glm::normalize(glm::vec3(0.2f, 0.1f, -1.0f));
  s.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
  s.camera.fromFile = true;
  return s;
}

render::RenderSettings settings(int spp, bool progressive) {
  render::RenderSettings rs;
  rs.width = rs.height = kSize;
  rs.mode = render::Mode::kPathtrace;
  rs.spp = spp;
  rs.progressive = progressive;
  rs.pathtrace.maxDepth = kMaxDepth;
  rs.pathtrace.seed = 11;
  return rs;
}

// Per pixel: the RGB mean.
std::vector<double> pixels(const std::vector<float>& px) {
  std::vector<double> out;
  for (size_t i = 0; i < px.size(); i += 4) out.push_back((px[i] + px[i + 1] + px[i + 2]) / 3.0);
  return out;
}

struct Checkpoint {
  int frames;
  double rmsError;  // over pixels, against the closed form
  double mean;      // over pixels
  double spread;    // standard deviation over pixels
  bool finite;
};

class AccumulationTest : public GlTest {};

TEST_F(AccumulationTest, TenThousandFramesStayFiniteAndConverge) {
  const scene::Scene s = furnaceBox();
  const double expected = kLe * (1.0 - std::pow(kAlbedo, kMaxDepth)) / (1.0 - kAlbedo);
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::Renderer r(programs, s, settings(1, true));
  std::vector<Checkpoint> checkpoints;
  std::vector<float> last;
  const auto start = std::chrono::steady_clock::now();
  for (int frame = 1; frame <= 10000; ++frame) {
    r.renderFrame();
    if (frame != 10 && frame != 100 && frame != 1000 && frame != 10000) continue;
    last = r.readLinear();
    Checkpoint c{frame, 0.0, 0.0, 0.0, true};
    const std::vector<double> v = pixels(last);
    for (float x : last) c.finite = c.finite && std::isfinite(x);
    for (double x : v) {
      c.mean += x / static_cast<double>(v.size());
      c.rmsError += (x - expected) * (x - expected) / static_cast<double>(v.size());
    }
    for (double x : v) c.spread += (x - c.mean) * (x - c.mean) / static_cast<double>(v.size() - 1);
    c.rmsError = std::sqrt(c.rmsError);
    c.spread = std::sqrt(c.spread);
    checkpoints.push_back(c);
    std::printf("frames %5d: mean %.6f (expected %.6f), rms error %.6f, spread %.6f\n", frame,
                c.mean, expected, c.rmsError, c.spread);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("10000 frames of %dx%d at 1 spp: %.1f s\n", kSize, kSize, seconds);
  EXPECT_EQ(r.accumulatedFrames(), 10000);
  EXPECT_EQ(r.pathtrace()->samplesSoFar(), 10000);
  ASSERT_EQ(checkpoints.size(), 4u);
  for (const Checkpoint& c : checkpoints) EXPECT_TRUE(c.finite) << "after " << c.frames;
  // Keeps converging: each tenfold of samples cuts the error about sqrt(10) = 3.2
  // times; with 64 pixels the measured ratio is good to about 10 %, so 2 is safe.
  for (size_t i = 1; i < checkpoints.size(); ++i)
    EXPECT_LT(checkpoints[i].rmsError * 2.0, checkpoints[i - 1].rmsError)
        << checkpoints[i - 1].frames << " -> " << checkpoints[i].frames << " frames";
  // The final mean lies within 4 standard errors of the closed form (the pixels are
  // independent estimates of the same value), and within 0.1 % besides.
  const Checkpoint& end = checkpoints.back();
  const double se = end.spread / std::sqrt(static_cast<double>(kSize * kSize));
  EXPECT_NEAR(end.mean, expected, 4.0 * se + 1e-6);
  EXPECT_NEAR(end.mean, expected, 1e-3 * expected);

  // 10,000 frames of one sample are bit for bit one frame of 10,000 samples: the
  // samples and the order of the compensated sums are the same.
  render::Renderer once(programs, s, settings(10000, false));
  once.renderFrame();
  EXPECT_EQ(once.readLinear(), last);
}

// Without `progressive`, every frame is a fresh image: the second frame equals the
// first (same seed, from sample 0) instead of averaging with it.
TEST_F(AccumulationTest, NotProgressiveRestartsEachFrame) {
  const scene::Scene s = furnaceBox();
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::Renderer r(programs, s, settings(2, false));
  r.renderFrame();
  const std::vector<float> first = r.readLinear();
  r.renderFrame();
  EXPECT_EQ(r.readLinear(), first);
  EXPECT_EQ(r.pathtrace()->samplesSoFar(), 2);
}

}  // namespace
}  // namespace voxgi::test
