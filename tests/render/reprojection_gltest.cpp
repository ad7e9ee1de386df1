// rtgi across camera moves: each pixel's history follows its surface, is dropped
// where the view reveals another one (no ghosts), is capped while the camera moves,
// and a still camera renders exactly as without reprojection.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "image/metrics.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/displayed_image.h"
#include "support/gl_fixture.h"
#include "support/scene_builder.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

class ReprojectionTest : public GlProgramsTest {
 protected:
  static render::RenderSettings settings(int size, bool reproject) {
    render::RenderSettings s;
    s.mode = render::Mode::kRtgi;
    s.width = size;
    s.height = size;
    s.voxels = 64;
    s.rtgi.reproject = reproject;
    return s;
  }
};

scene::Camera moved(scene::Camera c, glm::vec3 by) {
  c.position += by;
  return c;
}

// Pixels (RGBA) whose colour is zero.
bool black(const std::vector<float>& px, size_t i) {
  return px[i] == 0.0f && px[i + 1] == 0.0f && px[i + 2] == 0.0f;
}

TEST_F(ReprojectionTest, AStillCameraRendersExactlyAsWithout) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  render::Renderer on(*programs_, room, settings(32, true));
  render::Renderer off(*programs_, room, settings(32, false));
  for (int f = 0; f < 6; ++f) {
    on.renderFrame();
    off.renderFrame();
  }
  EXPECT_EQ(on.readLinear(), off.readLinear());
  EXPECT_EQ(on.accumulatedFrames(), 6);
}

// The square moves a sixth of the image to the left; where it was, the wall shows
// through with no trace of it, and where it still is, its history is kept.
TEST_F(ReprojectionTest, RevealedSurfacesCarryNoGhost) {
  const scene::Scene s = squareBeforeWall();
  // Every pixel traces; one in 4 a frame; the viewer's way (a frame budget at its
  // floor, one in 16, chosen by the work mask, starting sparse).
  for (int mode = 0; mode < 3; ++mode) {
    SCOPED_TRACE("mode " + std::to_string(mode));
    render::RenderSettings rs = settings(48, true);
    rs.jitter = false;  // the same sample positions as the fresh renderer's below
    rs.rtgi.interleave = mode == 1 ? 4 : 1;
    if (mode == 2) {
      rs.targetFps = 1000.0;
      rs.rtgi.sparseStart = true;
    }
    render::Renderer r(*programs_, s, rs);
    for (int f = 0; f < 32; ++f) r.renderFrame(s.camera);
    const scene::Camera b = moved(s.camera, glm::vec3(0.4f, 0.0f, 0.0f));
    r.renderFrame(b);
    EXPECT_EQ(r.accumulatedFrames(), 33);  // the move did not restart accumulation
    const std::vector<float> kept = r.readLinear();
    render::RenderSettings fs = settings(48, false);
    fs.jitter = false;
    render::Renderer fresh(*programs_, s, fs);
    fresh.renderFrame(b);
    const std::vector<float> expected = fresh.readLinear();
    size_t wall = 0, ghosts = 0, square = 0, withHistory = 0, dark = 0;
    float worst = 0.0f;
    for (size_t i = 0; i < kept.size(); i += 4) {
      if (black(expected, i)) {
        ++wall;
        ghosts += black(kept, i) ? 0 : 1;
        continue;
      }
      ++square;
      dark += black(kept, i) ? 1 : 0;
      withHistory += kept[i + 3] > 1.5f ? 1 : 0;
      worst = std::max(worst, std::abs(kept[i] - expected[i]) / expected[i]);
    }
    ASSERT_GT(wall, 500u);
    ASSERT_GT(square, 200u);
    EXPECT_EQ(ghosts, 0u);
    // Every square pixel has light: its history, its own sample, or (interleaved,
    // newly covered and not its turn) its traced neighbours'.
    EXPECT_EQ(dark, 0u);
    // Most of the square was in view before: its history followed it.
    EXPECT_GT(withHistory, square * 8 / 10) << withHistory << " of " << square;
    // Its light is uniform: reprojection (bilinear) and lending keep it exact.
    EXPECT_LT(worst, 0.01f);
  }
}

// In the Cornell room after a small step: the history is capped (16 frames), kept
// on most pixels, and the image is much nearer the converged one than a restart's
// first frame; once still, accumulation goes on past the cap.
TEST_F(ReprojectionTest, HistoryFollowsTheViewAndIsCapped) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  const int size = 48;
  const scene::Camera b = moved(room.camera, glm::vec3(0.06f, 0.03f, -0.05f));
  render::Renderer r(*programs_, room, settings(size, true));
  for (int f = 0; f < 32; ++f) r.renderFrame(room.camera);
  r.renderFrame(b);
  const std::vector<float> kept = r.readLinear();
  render::Renderer restart(*programs_, room, settings(size, false));
  for (int f = 0; f < 32; ++f) restart.renderFrame(room.camera);
  restart.renderFrame(b);
  EXPECT_EQ(restart.accumulatedFrames(), 1);
  const std::vector<float> first = restart.readLinear();
  for (int f = 0; f < 63; ++f) restart.renderFrame(b);
  const std::vector<float> converged = restart.readLinear();
  size_t withHistory = 0;
  float longest = 0.0f;
  for (size_t i = 3; i < kept.size(); i += 4) {
    withHistory += kept[i] > 1.5f ? 1 : 0;
    longest = std::max(longest, kept[i]);
  }
  EXPECT_LE(longest, 17.0f);  // 16 kept + this frame
  EXPECT_GT(withHistory, kept.size() / 4 * 8 / 10);
  // The error as displayed (clamped to [0, 1], as the default tonemap does): the
  // lamp's radiance, ten times display white, would otherwise weigh its few edge
  // pixels above the rest of the image.
  auto rgb = [&](const std::vector<float>& px) { return displayedImage(px, size, size); };
  const double keptError = image::errorMetrics(rgb(kept), rgb(converged)).rmse;
  const double firstError = image::errorMetrics(rgb(first), rgb(converged)).rmse;
  std::printf(
      "after a step: display RMSE against 64 still frames %.4f reprojected, %.4f restarted\n",
      keptError, firstError);
  // Measured 0.074 against 0.113: the mirror sphere and the lamp's edges keep no
  // history across a move, and at 48x48 they are a large share of the image.
  EXPECT_LT(keptError, 0.75 * firstError);
  for (int f = 0; f < 24; ++f) r.renderFrame(b);
  float after = 0.0f;
  const std::vector<float> still = r.readLinear();
  for (size_t i = 3; i < still.size(); i += 4) after = std::max(after, still[i]);
  EXPECT_GE(after, 40.0f);  // 16 + 1 + 24: no cap once still
}

// An animated box slides its own width: with the motion the G-buffer takes from
// the previous vertices, its pixels keep their history where it went, and where it
// was, the floor shows no red trace of it.
TEST_F(ReprojectionTest, MovingMeshesCarryTheirHistory) {
  scene::Scene s = scene::loadGltf(testDataDir() + "/animated/moving_box.gltf");
  render::RenderSettings rs = settings(48, true);
  rs.jitter = false;
  rs.revoxelize = true;  // the voxels' light follows the box too
  render::Renderer r(*programs_, s, rs);
  for (int f = 0; f < 16; ++f) r.renderFrame();
  s.pose(0.5);  // the box from x = -0.5 to 0: 0.5 m, its width
  r.posed();
  r.renderFrame();
  EXPECT_EQ(r.accumulatedFrames(), 17);
  const std::vector<float> kept = r.readLinear();
  render::RenderSettings fs = settings(48, false);
  fs.jitter = false;
  fs.revoxelize = true;
  render::Renderer fresh(*programs_, s, fs);
  fresh.renderFrame();
  const std::vector<float> expected = fresh.readLinear();
  size_t box = 0, withHistory = 0, floor = 0, ghosts = 0;
  for (size_t i = 0; i < kept.size(); i += 4) {
    if (expected[i] > 2.0f * expected[i + 1]) {  // the red box
      ++box;
      withHistory += kept[i + 3] > 1.5f ? 1 : 0;
    } else if (expected[i + 1] > 0.0f) {  // grey floor
      ++floor;
      ghosts += kept[i] > 2.0f * kept[i + 1] ? 1 : 0;
    }
  }
  ASSERT_GT(box, 40u);
  ASSERT_GT(floor, 500u);
  EXPECT_GT(withHistory, box * 7 / 10) << withHistory << " of " << box;
  EXPECT_EQ(ghosts, 0u);
  // A frame with no new pose has no motion: the next camera-still frame keeps
  // accumulating on every pixel.
  r.renderFrame();
  const std::vector<float> next = r.readLinear();
  size_t grew = 0, covered = 0;
  for (size_t i = 3; i < next.size(); i += 4) {
    if (expected[i - 3] + expected[i - 2] <= 0.0f) continue;
    ++covered;
    grew += next[i] > kept[i] ? 1 : 0;
  }
  EXPECT_EQ(grew, covered);
}

// The box's shadow moves with it (the default sun, from above and to the side): the
// floor it leaves keeps its history, which the disocclusion tests cannot reject, but
// whose light no longer matches the floor's around it. Two frames after the move
// those pixels show the light of a fresh render, not a trail of the old shadow;
// floor the move did not change keeps its history.
TEST_F(ReprojectionTest, AMovedShadowLeavesNoTrail) {
  constexpr int kSize = 64;
  // Seen from above, where the shadow falls beside the box rather than behind it.
  auto load = [] {
    scene::Scene s = scene::loadGltf(testDataDir() + "/animated/moving_box.gltf");
    s.camera.position = glm::vec3(-0.4f, 2.5f, 0.8f) - glm::vec3(s.origin);
    s.camera.forward = glm::normalize(glm::vec3(0.0f, -2.5f, -1.0f));
    return s;
  };
  auto boxSettings = [](bool reproject) {
    render::RenderSettings rs = settings(kSize, reproject);
    rs.jitter = false;
    rs.revoxelize = true;  // the voxels' light follows the box too
    return rs;
  };
  auto run = [&](bool dropStale, std::vector<float>* before) {
    scene::Scene s = load();
    render::RenderSettings rs = boxSettings(true);
    rs.rtgi.dropStaleHistory = dropStale;
    render::Renderer r(*programs_, s, rs);
    for (int f = 0; f < 16; ++f) r.renderFrame();
    if (before) *before = r.readLinear();
    s.pose(0.5);  // the box slides its own width
    r.posed();
    r.renderFrame();
    r.renderFrame();
    return r.readLinear();
  };
  std::vector<float> before;
  const std::vector<float> kept = run(true, &before);
  const std::vector<float> trail = run(false, nullptr);
  scene::Scene s = load();
  s.pose(0.5);
  render::Renderer fresh(*programs_, s, boxSettings(false));
  for (int f = 0; f < 16; ++f) fresh.renderFrame();
  const std::vector<float> expected = fresh.readLinear();
  // Not the red box (lit: red well above green and bright); the floor in the box's
  // shadow is dim and reddened by the light the box bounces onto it.
  auto floorPixel = [](const std::vector<float>& px, size_t i) {
    return px[i + 1] > 0.0f && !(px[i] > 2.0f * px[i + 1] && px[i] > 0.25f);
  };
  double uncovered = 0.0, keptSum = 0.0, trailSum = 0.0, freshSum = 0.0;
  size_t unchanged = 0, unchangedKept = 0;
  for (size_t i = 0; i < kept.size(); i += 4) {
    if (!floorPixel(expected, i) || !floorPixel(before, i)) continue;
    if (before[i + 1] < 0.3f * expected[i + 1]) {  // was in the shadow, is lit now
      ++uncovered;
      keptSum += kept[i + 1];
      trailSum += trail[i + 1];
      freshSum += expected[i + 1];
    } else if (std::abs(before[i + 1] - expected[i + 1]) < 0.1f * expected[i + 1]) {
      ++unchanged;
      unchangedKept += kept[i + 3] > 2.5f ? 1 : 0;
    }
  }
  ASSERT_GT(uncovered, 20.0);
  ASSERT_GT(unchanged, 500u);
  std::printf(
      "uncovered shadow: %.0f pixels, kept %.3f and without the test %.3f of a fresh render; "
      "unchanged floor keeping its history %zu of %zu\n",
      uncovered, keptSum / freshSum, trailSum / freshSum, unchangedKept, unchanged);
  // Measured 0.983, and 0.298 without the test: 2 lit frames over 16 in the shadow.
  EXPECT_NEAR(keptSum / freshSum, 1.0, 0.1);
  EXPECT_LT(trailSum / freshSum, 0.5);
  EXPECT_GT(unchangedKept, unchanged * 9 / 10);
}

// A thin white bar crosses a dark floor (a twentieth of its albedo), its own width
// every frame: where it was two frames before, the floor shows no trace of it. rtgi's
// history follows the floor, not the bar (the material test: the bar lies on the
// floor, whose normal and plane it shares), at render scale 1 and 0.5 (the
// upsampler's history too) and under the viewer's frame budget (a pixel that does not
// trace borrows its neighbours' light).
TEST_F(ReprojectionTest, AThinBrightObjectLeavesNoTrail) {
  constexpr int kSize = 192;
  const std::string file = testDataDir() + "/animated/thin_bar.gltf";
  auto barSettings = [](bool reproject, float scale, bool budget) {
    render::RenderSettings rs = settings(kSize, reproject);
    rs.jitter = false;
    rs.revoxelize = true;  // the voxels' light follows the bar too
    rs.renderScale = scale;
    if (budget) rs.targetFps = 1000.0;  // the budget's floor: one pixel in 16 traces
    return rs;
  };
  auto lum = [](const std::vector<float>& px, size_t i) {
    return 0.2126f * px[i] + 0.7152f * px[i + 1] + 0.0722f * px[i + 2];
  };
  constexpr double kFrame = 1.0 / 30.0;  // the bar's width at its speed
  // Where the bar is at time t: far brighter than the floor in a fresh render.
  auto barAt = [&](double t, float* floorLevel) {
    scene::Scene s = scene::loadGltf(file);
    s.pose(t);
    render::Renderer fresh(*programs_, s, barSettings(false, 1.0f, false));
    for (int f = 0; f < 4; ++f) fresh.renderFrame();
    const std::vector<float> px = fresh.readLinear();
    std::vector<float> l;
    for (size_t i = 0; i < px.size(); i += 4) l.push_back(lum(px, i));
    std::vector<float> sorted = l;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    *floorLevel = sorted[sorted.size() / 2];
    std::vector<bool> bar(l.size());
    for (size_t i = 0; i < l.size(); ++i) bar[i] = l[i] > 5.0f * *floorLevel;
    return bar;
  };
  struct Case {
    float scale;
    bool budget;
  };
  for (const Case c : {Case{1.0f, false}, Case{0.5f, false}, Case{0.5f, true}}) {
    SCOPED_TRACE(testing::Message() << "scale " << c.scale << (c.budget ? ", budget" : ""));
    scene::Scene s = scene::loadGltf(file);
    render::Renderer r(*programs_, s, barSettings(true, c.scale, c.budget));
    for (int f = 0; f < 8; ++f) r.renderFrame();
    for (int f = 1; f <= 20; ++f) {
      s.pose(f * kFrame);
      r.posed();
      r.renderFrame();
      if (f % 10 != 0) continue;
      float floorLevel = 0.0f, unused = 0.0f;
      const std::vector<bool> now = barAt(f * kFrame, &floorLevel);
      const std::vector<bool> one = barAt((f - 1) * kFrame, &unused);
      const std::vector<bool> two = barAt((f - 2) * kFrame, &unused);
      const std::vector<float> kept = r.readLinear();
      // Below scale 1 an output pixel shows the internal image filtered over its
      // pixel and the next: the bar's light spreads that far from where it was.
      const int spread = c.scale < 1.0f ? static_cast<int>(std::ceil(1.0f / c.scale)) : 0;
      auto near = [&](const std::vector<bool>& mask, int x, int y) {
        for (int dy = -spread; dy <= spread; ++dy)
          for (int dx = -spread; dx <= spread; ++dx) {
            const int u = x + dx, v = y + dy;
            if (u >= 0 && v >= 0 && u < kSize && v < kSize && mask[v * kSize + u]) return true;
          }
        return false;
      };
      size_t bar = 0, shown = 0, floor = 0, trail = 0;
      for (size_t p = 0; p < now.size(); ++p) {
        const int x = static_cast<int>(p) % kSize, y = static_cast<int>(p) / kSize;
        const bool bright = lum(kept, 4 * p) > 3.0f * floorLevel;
        if (now[p]) {
          ++bar;
          shown += bright ? 1 : 0;
        } else if (!near(now, x, y) && !near(one, x, y) && !near(two, x, y)) {
          ++floor;
          trail += bright ? 1 : 0;
        }
      }
      ASSERT_GT(bar, 300u);
      ASSERT_GT(floor, 20000u);
      EXPECT_EQ(trail, 0u) << "frame " << f << ": " << trail << " floor pixels trail the bar";
      // The bar is drawn where it is.
      EXPECT_GT(shown, bar * 8 / 10) << "frame " << f << ": " << shown << " of " << bar;
    }
  }
}

}  // namespace
}  // namespace voxgi::test
