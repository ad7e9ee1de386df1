// What the viewer asks of the renderer: a per-frame camera, resizing, knobs, and
// accumulation restarting on any change; the fixed-size `render` path is unchanged.
#include <gtest/gtest.h>

#include "core/log.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

class RendererTest : public GlTest {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    if (!context_) return;
    scene_ = scene::loadGltf(cornellRoom());
    programs_ = std::make_unique<gl::ProgramCache>(sourceDir() + "/shaders");
  }
  void TearDown() override {
    programs_.reset();
    GlTest::TearDown();
  }
  render::RenderSettings settings(int w, int h) const {
    render::RenderSettings s;
    s.mode = render::Mode::kRaster;
    s.width = w;
    s.height = h;
    return s;
  }
  scene::Scene scene_;
  std::unique_ptr<gl::ProgramCache> programs_;
};

TEST_F(RendererTest, SceneCameraAndExplicitCameraAgree) {
  render::Renderer r(*programs_, scene_, settings(48, 40));
  r.renderFrame();
  const auto a = r.readDisplay();
  r.renderFrame(scene_.camera);
  EXPECT_EQ(r.readDisplay(), a);
  scene::Camera moved = scene_.camera;
  moved.position += 0.3f * moved.forward;
  r.renderFrame(moved);
  EXPECT_NE(r.readDisplay(), a);
}

TEST_F(RendererTest, ResizedMatchesFresh) {
  render::Renderer resized(*programs_, scene_, settings(64, 64));
  resized.renderFrame();
  resized.resize(96, 48);
  EXPECT_EQ(resized.settings().width, 96);
  EXPECT_EQ(resized.accumulatedFrames(), 0);
  resized.renderFrame();
  EXPECT_EQ(resized.readDisplay().size(), 96u * 48u * 4u);
  render::Renderer fresh(*programs_, scene_, settings(96, 48));
  fresh.renderFrame();
  EXPECT_EQ(resized.readDisplay(), fresh.readDisplay());
  EXPECT_EQ(resized.readLinear(), fresh.readLinear());
  EXPECT_THROW(resized.resize(0, 10), voxgi::Error);
  EXPECT_EQ(resized.settings().width, 96);  // a refused size leaves the targets alone
}

// The warm-up compiles and builds at a small size, and leaves nothing of that size
// in the frames after it: rtgi's image is the one a warm-up frame at full size,
// thrown away, would have led to (the voxels made and refined once, as by it).
TEST_F(RendererTest, WarmUpLeavesTheImageAsAFullSizeFrameWould) {
  render::RenderSettings s = settings(96, 64);
  s.mode = render::Mode::kRtgi;
  s.rtgi.seed = 7;
  render::Renderer warmed(*programs_, scene_, s);
  warmed.warmUp();
  EXPECT_EQ(warmed.settings().width, 96);
  EXPECT_EQ(warmed.settings().height, 64);
  EXPECT_EQ(warmed.accumulatedFrames(), 0);
  render::Renderer full(*programs_, scene_, s);
  full.renderFrame();
  full.restartAccumulation();
  for (int f = 0; f < 2; ++f) {
    warmed.renderFrame();
    full.renderFrame();
  }
  EXPECT_EQ(warmed.readLinear().size(), 96u * 64u * 4u);
  EXPECT_EQ(warmed.readLinear(), full.readLinear());
}

TEST_F(RendererTest, AccumulationRestartsOnAnyChange) {
  render::Renderer r(*programs_, scene_, settings(32, 32));
  r.renderFrame();
  r.renderFrame();
  EXPECT_EQ(r.accumulatedFrames(), 2);
  r.resize(32, 32);  // same size: nothing changes
  r.setMode(render::Mode::kRaster);
  EXPECT_EQ(r.accumulatedFrames(), 2);
  scene::Camera c = scene_.camera;
  c.forward = glm::normalize(c.forward + glm::vec3(0.01f, 0.0f, 0.0f));
  r.renderFrame(c);
  EXPECT_EQ(r.accumulatedFrames(), 1);
  r.renderFrame(c);
  EXPECT_EQ(r.accumulatedFrames(), 2);
  auto knobs = r.knobs();
  ASSERT_FALSE(knobs.empty());
  knobs[0].set(knobs[0].get());
  EXPECT_EQ(r.accumulatedFrames(), 0);
  r.renderFrame(c);
  r.restartAccumulation();
  EXPECT_EQ(r.accumulatedFrames(), 0);
}

// rtgi's indirect rays on the triangles read the voxel bounces apart from the direct
// light, which an octree made for dvr does not keep: switching modes makes it again,
// and the image is a fresh rtgi renderer's.
TEST_F(RendererTest, SwitchingToRtgiGivesAFreshRtgiImage) {
  render::RenderSettings s = settings(32, 32);
  s.mode = render::Mode::kDvr;
  s.voxels = 32;
  render::Renderer switched(*programs_, scene_, s);
  switched.renderFrame();
  switched.setMode(render::Mode::kRtgi);
  s.mode = render::Mode::kRtgi;
  render::Renderer fresh(*programs_, scene_, s);
  for (int f = 0; f < 3; ++f) {
    switched.renderFrame();
    fresh.renderFrame();
  }
  EXPECT_EQ(switched.readLinear(), fresh.readLinear());
}

// Under a frame budget, the voxels' light is not refined while the view moves (the
// frame's time goes to the pixels); it is without a budget, and once the view stops.
TEST_F(RendererTest, VoxelLightWaitsWhileABudgetedViewMoves) {
  render::RenderSettings s = settings(32, 32);
  s.mode = render::Mode::kRtgi;
  s.voxels = 32;
  auto refined = [](const render::Renderer& r) {
    for (const gl::StageTime& t : r.lastStages())
      if (t.stage == Stage::kRefine) return true;
    return false;
  };
  for (double fps : {0.0, 30.0}) {
    s.targetFps = fps;
    render::Renderer r(*programs_, scene_, s);
    scene::Camera camera = scene_.camera;
    r.renderFrame(camera);
    r.renderFrame(camera);
    EXPECT_TRUE(refined(r)) << "fps " << fps;  // still
    camera.position += 0.05f * camera.forward;
    r.renderFrame(camera);
    EXPECT_EQ(refined(r), fps == 0.0) << "fps " << fps;  // moving
    r.renderFrame(camera);
    EXPECT_TRUE(refined(r)) << "fps " << fps;  // still again
  }
}

TEST_F(RendererTest, KnobsDriveTheTonemap) {
  render::Renderer r(*programs_, scene_, settings(32, 32));
  auto knobs = r.knobs();
  ASSERT_EQ(knobs.size(), 2u);  // raster has none; the tonemap's exposure and operator
  EXPECT_EQ(knobs[0].label, "exposure");
  EXPECT_EQ(knobs[0].get(), 1.0);
  EXPECT_EQ(knobs[1].kind, render::Knob::Kind::kChoice);
  EXPECT_EQ(knobs[1].choices, (std::vector<std::string>{"clamp", "aces"}));
  knobs[0].set(0.25);
  knobs[1].set(1);
  EXPECT_EQ(r.settings().tonemap.exposure, 0.25f);
  EXPECT_EQ(r.settings().tonemap.op, render::Tonemap::kAces);
  r.renderFrame();
  render::RenderSettings s = settings(32, 32);
  s.tonemap.exposure = 0.25f;
  s.tonemap.op = render::Tonemap::kAces;
  render::Renderer expected(*programs_, scene_, s);
  expected.renderFrame();
  EXPECT_EQ(r.readDisplay(), expected.readDisplay());
}

}  // namespace
}  // namespace voxgi::test
