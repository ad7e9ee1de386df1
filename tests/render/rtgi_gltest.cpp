// rtgi's hard cases on llvmpipe: no NaN or Inf wherever the camera is, no light
// through closed walls, no flicker once converged, the same image every run, and
// convergence towards the path tracer on both reference scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "image/metrics.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/scene_builder.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

size_t nonFinite(const std::vector<float>& px) {
  return static_cast<size_t>(
      std::count_if(px.begin(), px.end(), [](float v) { return !std::isfinite(v); }));
}

double meanOf(const std::vector<float>& rgba) {
  double sum = 0.0;
  for (size_t i = 0; i < rgba.size(); i += 4) sum += (rgba[i] + rgba[i + 1] + rgba[i + 2]) / 3.0;
  return sum / static_cast<double>(rgba.size() / 4);
}

image::Image toImage(const std::vector<float>& rgba, int size) {
  image::Image im;
  im.width = size;
  im.height = size;
  im.channels = 3;
  for (size_t i = 0; i < rgba.size(); i += 4)
    im.pixels.insert(im.pixels.end(), {rgba[i], rgba[i + 1], rgba[i + 2]});
  return im;
}

class RtgiTest : public GlProgramsTest {
 protected:
  static render::RenderSettings settings(int size, int voxels, render::Mode mode) {
    render::RenderSettings s;
    s.mode = mode;
    s.width = size;
    s.height = size;
    s.voxels = voxels;
    s.spp = 256;
    return s;
  }

  // `frames` frames of accumulation from `camera`; linear RGBA. The NaN or Inf
  // values the renderer replaced on the way go to lastNonfinite_.
  std::vector<float> render(const scene::Scene& s, const render::RenderSettings& rs, int frames,
                            const scene::Camera& camera) {
    render::Renderer r(*programs_, s, rs);
    for (int f = 0; f < frames; ++f) r.renderFrame(camera);
    lastNonfinite_ = r.nonfiniteTerms();
    return r.readLinear();
  }
  uint32_t lastNonfinite_ = 0;

  // A sealed room, walls `thickness` thick, a dim light inside and a light 1000 times
  // brighter just outside; the camera inside. Returns the mean radiance with the
  // outside light on and off.
  std::pair<double, double> sealedRoom(float thickness,
                                       render::RtgiPass::Settings::IndirectMethod method =
                                           render::RtgiPass::Settings::IndirectMethod::kRays,
                                       int bounces = voxel::Octree::Settings::kAllBounces,
                                       int frames = 8) {
    scene::Camera cam;
    cam.position = glm::vec3(0.0f, 0.0f, 0.8f);
    cam.forward = glm::vec3(0.0f, 0.0f, -1.0f);
    cam.up = glm::vec3(0.0f, 1.0f, 0.0f);
    render::RenderSettings rs = settings(48, 64, render::Mode::kRtgi);
    rs.rtgi.indirectMethod = method;
    rs.octree.bounces = bounces;
    const double off = meanOf(render(sealedBox(thickness, false), rs, frames, cam));
    const double on = meanOf(render(sealedBox(thickness, true), rs, frames, cam));
    return {on, off};
  }
};

// Wherever the camera is: inside the diffuse sphere, inside the wall's voxels,
// looking exactly along the axes, at grazing angles; and on the dark plane.
TEST_F(RtgiTest, NoNanOrInfAnywhere) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  const render::RenderSettings rs = settings(48, 64, render::Mode::kRtgi);
  std::vector<scene::Camera> cameras;
  scene::Camera c = room.camera;
  cameras.push_back(c);
  c.position = glm::vec3(-0.45f, 0.4f, -0.35f) - glm::vec3(room.origin);  // in the sphere
  cameras.push_back(c);
  c.position = glm::vec3(-1.0f, 1.0f, 0.0f) - glm::vec3(room.origin);  // in the left wall
  c.forward = glm::vec3(1.0f, 0.0f, 0.0f);                             // along +x
  cameras.push_back(c);
  c.position = glm::vec3(0.0f, 0.001f, 0.9f) - glm::vec3(room.origin);  // on the floor, grazing
  c.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  cameras.push_back(c);
  c.position = glm::vec3(0.0f, 1.0f, 0.0f) - glm::vec3(room.origin);  // straight down
  c.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  c.up = glm::vec3(0.0f, 0.0f, -1.0f);
  cameras.push_back(c);
  // And with a head lamp: a point light at the eye, where the half vector of the
  // light equals the view.
  scene::Scene lamp = room;
  scene::Light head;
  head.position = room.camera.position;
  head.intensity = 2.0f;
  lamp.lights.push_back(head);
  {
    const auto px = render(lamp, rs, 3, room.camera);
    EXPECT_EQ(nonFinite(px), 0u) << "head lamp";
    EXPECT_EQ(lastNonfinite_, 0u) << "head lamp";
  }
  for (size_t i = 0; i < cameras.size(); ++i) {
    const auto px = render(room, rs, 3, cameras[i]);
    EXPECT_EQ(nonFinite(px), 0u) << "camera " << i;
    // Nor a NaN or Inf that accumulation or the octree replaced on the way.
    EXPECT_EQ(lastNonfinite_, 0u) << "camera " << i;
  }
  const scene::Scene plane = scene::loadGltf(darkPlane());
  const auto px = render(plane, rs, 3, plane.camera);
  EXPECT_EQ(nonFinite(px), 0u);
  EXPECT_EQ(lastNonfinite_, 0u);
  EXPECT_GT(meanOf(px), 0.0);
  // dvr sees the same volume without NaN either.
  EXPECT_EQ(nonFinite(render(room, settings(48, 64, render::Mode::kDvr), 1, cameras[1])), 0u);
}

// Walls 4 voxels thick, and walls a third of a voxel thick: as dark inside with the
// bright light outside as without it. A voxel of a thin wall holds both its faces
// (its normals cancel) and keeps the light of its two sides apart (octree.glsl,
// leafAxis): lit from outside, its inner side stays dark, and neither the room's
// voxels nor the rays from the pixels read the outer side from inside. One light for
// both sides, as before, leaked 0.215 of the outside light's relative strength.
TEST_F(RtgiTest, ClosedWallsDoNotLeakLight) {
  const auto [on, off] = sealedRoom(0.25f);
  ASSERT_GT(off, 0.0);
  EXPECT_LE(std::abs(on - off), 1e-6 * off) << "on " << on << " off " << off;
  const auto [thinOn, thinOff] = sealedRoom(0.02f);
  std::printf("sealed room: walls 1/3 voxel thick, on %.9g off %.9g\n", thinOn, thinOff);
  EXPECT_LE(std::abs(thinOn - thinOff), 1e-6 * thinOff);
}

// The same with one bounce (no voxel light behind the indirect hits), where only a
// pixel's first sample reads the voxels' whole light at its hit
// (rtgi_voxel_light.glsl): the side of the wall it faces. Reading one light for both
// sides leaked 0.28 of the outside light's strength through that first sample.
TEST_F(RtgiTest, ThinWallsLeakNothingAtOneBounce) {
  using Method = render::RtgiPass::Settings::IndirectMethod;
  for (const int frames : {1, 8}) {
    const auto [on, off] = sealedRoom(0.02f, Method::kRays, 1, frames);
    ASSERT_GT(off, 0.0);
    EXPECT_LE(std::abs(on - off), 1e-6 * off) << frames << " frames: on " << on << " off " << off;
  }
}

// The same rooms with cone-traced indirect light (--indirect cones): inner nodes
// holding both sides of a wall give the cones no light, and the voxels' light no
// longer crosses the thin walls. One light for both sides of a leaf leaked 0.206.
TEST_F(RtgiTest, ConesDoNotLeakThroughClosedWalls) {
  using Method = render::RtgiPass::Settings::IndirectMethod;
  for (const float thickness : {0.25f, 0.02f}) {
    const auto [on, off] = sealedRoom(thickness, Method::kCones);
    ASSERT_GT(off, 0.0);
    EXPECT_LE(std::abs(on - off), 1e-6 * off)
        << "walls " << thickness << ": on " << on << " off " << off;
  }
}

// Cones give the Cornell room finite indirect light of about the strength the rays
// converge to: the indirect term (the image less the image without the indirect
// effect) of one cone frame against 64 frames of rays. Measured 0.90x: the cones
// are biased low where coarse nodes mix both sides of a surface (they occlude
// without light); the bound leaves room for that, not for a lost or doubled term.
TEST_F(RtgiTest, ConesGiveIndirectLightLikeRays) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  render::RenderSettings rs = settings(48, 64, render::Mode::kRtgi);
  rs.jitter = false;
  const auto rays = render(room, rs, 64, room.camera);
  rs.rtgi.indirectMethod = render::RtgiPass::Settings::IndirectMethod::kCones;
  const auto cones = render(room, rs, 1, room.camera);
  EXPECT_EQ(nonFinite(cones), 0u);
  rs.effects = "-indirect";
  const double direct = meanOf(render(room, rs, 1, room.camera));
  const double raysIndirect = meanOf(rays) - direct;
  const double conesIndirect = meanOf(cones) - direct;
  std::printf("cornell room indirect term: rays %.4f, cones %.4f (ratio %.3f)\n", raysIndirect,
              conesIndirect, conesIndirect / raysIndirect);
  ASSERT_GT(raysIndirect, 0.0);
  EXPECT_GT(conesIndirect, 0.0);
  EXPECT_NEAR(conesIndirect / raysIndirect, 1.0, 0.25);
}

// With cones, a glossy surface's reflection is one cone whose aperture follows its
// roughness: the Cornell room's mirror sphere made glossy (roughness 0.3) reflects,
// in one cone frame, within 35% of the light 64 ray frames find (the specular term:
// the image less the image without the specular effect, the same seeds), and the
// cone's term is smooth (per pixel, from frame 1 to 2 it moves only with the voxels'
// light) where one ray a frame is noise.
TEST_F(RtgiTest, GlossyConeReflectsLikeRays) {
  scene::Scene room = scene::loadGltf(cornellRoom());
  int glossy = 0;
  for (scene::Material& m : room.materials)
    if (m.metallic > 0.5f) {
      m.roughness = 0.3f;
      ++glossy;
    }
  ASSERT_GE(glossy, 1);
  render::RenderSettings rs = settings(48, 64, render::Mode::kRtgi);
  rs.jitter = false;
  auto specularTerm = [&](int frames) {
    std::vector<float> all = render(room, rs, frames, room.camera);
    render::RenderSettings without = rs;
    without.effects = "-specular";
    const std::vector<float> rest = render(room, without, frames, room.camera);
    for (size_t i = 0; i < all.size(); ++i) all[i] -= rest[i];
    return all;
  };
  // RMS of the per-pixel change from a to b over `mean`, colour channels. The rays'
  // term of one frame is a difference of two noisy images, whose own mean may be
  // near 0: their change is taken over the 64 frames' mean.
  auto change = [](const std::vector<float>& a, const std::vector<float>& b, double mean) {
    double d2 = 0.0;
    for (size_t i = 0; i < a.size(); ++i)
      if (i % 4 != 3) d2 += (a[i] - b[i]) * (a[i] - b[i]);
    return std::sqrt(d2 / static_cast<double>(a.size() / 4 * 3)) / mean;
  };
  const double rays = meanOf(specularTerm(64));
  const double raysChange = change(specularTerm(1), specularTerm(2), rays);
  rs.rtgi.indirectMethod = render::RtgiPass::Settings::IndirectMethod::kCones;
  const std::vector<float> cone = specularTerm(1);
  EXPECT_EQ(nonFinite(cone), 0u);
  const double cones = meanOf(cone);
  const double conesChange = change(cone, specularTerm(2), cones);
  std::printf(
      "glossy sphere (roughness 0.3) specular term: rays %.5f, cone %.5f (ratio %.3f); change "
      "frame 1 to 2: rays %.3f, cone %.4f\n",
      rays, cones, cones / rays, raysChange, conesChange);
  ASSERT_GT(rays, 0.0);
  EXPECT_GT(cones, 0.0);
  EXPECT_NEAR(cones / rays, 1.0, 0.35);
  // The cone's term moves only as the voxels' light is refined from frame to frame
  // (measured 0.087); one ray a frame, which also carries its share of the lamp's
  // highlight (RTGI_HIGHLIGHT_MIS), moves it by 22 (over the 64 frames' mean; over
  // its own frame's mean it was 47, until that mean came out negative).
  EXPECT_LT(conesChange, 0.15);
  EXPECT_GT(raysChange, 10.0 * conesChange);
}

// How what a still camera shows changes from one frame to the next.
struct FrameChange {
  double changedShare;  // of the display's colour channels, by more than 2 of 255 levels
  double relRms;        // RMS change of the linear image over its mean
};

FrameChange changeAfter(render::Renderer& r, int frames) {
  while (r.accumulatedFrames() < frames) r.renderFrame();
  const auto a = r.readDisplay();
  const auto la = r.readLinear();
  r.renderFrame();
  const auto b = r.readDisplay();
  const auto lb = r.readLinear();
  size_t changed = 0;
  for (size_t i = 0; i < a.size(); ++i)
    if ((i % 4) != 3 && std::abs(int(a[i]) - int(b[i])) > 2) ++changed;
  double diff2 = 0.0;
  for (size_t i = 0; i < la.size(); ++i)
    if (i % 4 != 3) diff2 += (la[i] - lb[i]) * (la[i] - lb[i]);  // alpha counts samples
  EXPECT_TRUE(std::isfinite(diff2));
  const double channels = static_cast<double>(a.size() / 4 * 3);
  return FrameChange{static_cast<double>(changed) / channels,
                     std::sqrt(diff2 / channels) / meanOf(la)};
}

// Converged still image: between frames n and n + 1 of accumulation the mean moves
// by 1/(n + 1) of one frame's deviation. With pixel centres (no sub-pixel offset),
// the lighting's flicker alone, from frame 64 to 65: no more than 0.5% of the
// display's channels change by more than 2 of 255 levels, and the relative RMS
// change is below 1%. With the offset, an edge pixel's samples fall on either side
// of the edge and its mean moves by its contrast / (n + 1), the antialiasing
// converging: the change from frame 256 to 257 is at most 0.4x the change from 64 to
// 65 (1/4 for a change that falls as 1/n).
template <class Programs>
void expectStillImageSettles(Programs& programs, const scene::Scene& room,
                             render::RenderSettings rs, const char* what) {
  rs.jitter = false;
  render::Renderer centred(programs, room, rs);
  const FrameChange still = changeAfter(centred, 64);
  rs.jitter = true;
  render::Renderer jittered(programs, room, rs);
  const FrameChange at64 = changeAfter(jittered, 64);
  const FrameChange at256 = changeAfter(jittered, 256);
  std::printf(
      "%s, frame 64 -> 65 at pixel centres: %.3f%% of channels change > 2 levels, relative "
      "RMS %.4f; with the sub-pixel offset: RMS %.4f (64 -> 65), %.4f (256 -> 257)\n",
      what, 100.0 * still.changedShare, still.relRms, at64.relRms, at256.relRms);
  EXPECT_LE(still.changedShare, 0.005);
  EXPECT_LT(still.relRms, 0.01);
  EXPECT_LT(at256.relRms, 0.4 * at64.relRms);
}

TEST_F(RtgiTest, ConvergedImageDoesNotFlicker) {
  expectStillImageSettles(*programs_, scene::loadGltf(cornellRoom()),
                          settings(64, 64, render::Mode::kRtgi), "running mean");
}

// The denoised image of a still camera settles as the mean does, within the same
// bounds (the filter fades as the noise it measures falls, and never feeds back
// into the history).
TEST_F(RtgiTest, DenoisedStillImageDoesNotFlicker) {
  render::RenderSettings rs = settings(64, 64, render::Mode::kRtgi);
  rs.rtgi.denoise = true;
  expectStillImageSettles(*programs_, scene::loadGltf(cornellRoom()), rs, "denoised");
}

// A textured, normal-mapped model (Avocado): its G-buffer is jittered, so each frame
// reads its base colour and normals at other points of the textures while the mean
// averages them all. The denoised image moves from frame to frame by little more than
// the mean it filters. While the filter divided the mean by this frame's base colour
// and stopped at this frame's mapped normals it moved by 2.39x and 2.25x as much
// (64x64, frame 32 to 33, seeds 7 and 8); with the base colour's running mean and the
// surface's own normal (rtgi_denoise.glsl), 1.72x and 1.53x. Bound: 2.
TEST_F(RtgiTest, DenoisedTexturedImageMovesAsItsMean) {
  const scene::Scene s = scene::loadGltf(samplesDir() + "/avocado/Avocado.gltf");
  render::RenderSettings rs = settings(64, 64, render::Mode::kRtgi);
  rs.rtgi.seed = rs.octree.seed = 7;
  render::Renderer raw(*programs_, s, rs);
  const FrameChange mean = changeAfter(raw, 32);
  rs.rtgi.denoise = true;
  render::Renderer denoised(*programs_, s, rs);
  const FrameChange filtered = changeAfter(denoised, 32);
  std::printf(
      "avocado, frame 32 -> 33: the mean moves by %.4f RMS, the denoised image %.4f (%.2fx)\n",
      mean.relRms, filtered.relRms, filtered.relRms / mean.relRms);
  EXPECT_LT(filtered.relRms, 2.0 * mean.relRms);
}

// The same settings give the same image, run after run; another seed does not.
TEST_F(RtgiTest, SameSeedSameImage) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  render::RenderSettings rs = settings(32, 64, render::Mode::kRtgi);
  const auto a = render(room, rs, 4, room.camera);
  EXPECT_EQ(a, render(room, rs, 4, room.camera));
  rs.rtgi.seed = 99;
  EXPECT_NE(a, render(room, rs, 4, room.camera));
}

// Interleaving: with N = 4, after the first frame (every pixel) and 4 x 8 more, every
// pixel holds exactly 9 samples, and the image agrees with 9 frames traced in full.
TEST_F(RtgiTest, InterleavedTracingGivesEveryPixelItsTurn) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  render::RenderSettings rs = settings(50, 64, render::Mode::kRtgi);  // not a multiple of 4
  const auto full = render(room, rs, 9, room.camera);
  rs.rtgi.interleave = 4;
  const auto interleaved = render(room, rs, 1 + 4 * 8, room.camera);
  size_t wrongCount = 0;
  for (size_t i = 3; i < interleaved.size(); i += 4) wrongCount += interleaved[i] != 9.0f;
  EXPECT_EQ(wrongCount, 0u);
  EXPECT_NEAR(meanOf(interleaved) / meanOf(full), 1.0, 0.02);
  const image::ErrorMetrics m = image::errorMetrics(toImage(interleaved, 50), toImage(full, 50));
  EXPECT_LT(m.relMse, 0.05);
}

// A sparse start: the first frame traces the pattern's share only; the pixels still
// waiting show their traced neighbours' light with a sample count of 0 (an image as
// bright as the converged one, not one with 15 of 16 pixels black), and after 16
// frames every pixel holds exactly its one sample.
TEST_F(RtgiTest, SparseStartTracesItsShareAndLendsTheRest) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  render::RenderSettings rs = settings(48, 64, render::Mode::kRtgi);
  const auto converged = render(room, rs, 32, room.camera);
  rs.rtgi.interleave = 16;
  rs.rtgi.sparseStart = true;
  render::Renderer r(*programs_, room, rs);
  r.renderFrame(room.camera);
  EXPECT_DOUBLE_EQ(r.rtgi()->lastTracedFraction(), 1.0 / 16.0);
  const auto first = r.readLinear();
  EXPECT_EQ(nonFinite(first), 0u);
  size_t traced = 0, dark = 0;
  for (size_t i = 0; i < first.size(); i += 4) {
    EXPECT_TRUE(first[i + 3] == 0.0f || first[i + 3] == 1.0f) << first[i + 3];
    traced += first[i + 3] == 1.0f;
    dark += first[i] + first[i + 1] + first[i + 2] == 0.0f;
  }
  EXPECT_EQ(traced, size_t{48 * 48 / 16});
  // Lent light reaches pixels as often as their own first sample would: black pixels
  // (a ray that found no light) no more often than in a first frame traced in full.
  render::RenderSettings fullRate = settings(48, 64, render::Mode::kRtgi);
  const auto full = render(room, fullRate, 1, room.camera);
  size_t darkFull = 0;
  for (size_t i = 0; i < full.size(); i += 4)
    darkFull += full[i] + full[i + 1] + full[i + 2] == 0.0f;
  std::printf("black pixels in the first frame: sparse %zu, full %zu of %d\n", dark, darkFull,
              48 * 48);
  EXPECT_LE(dark, darkFull + 10);
  EXPECT_NEAR(meanOf(first) / meanOf(converged), 1.0, 0.25);
  for (int f = 1; f < 16; ++f) r.renderFrame(room.camera);
  const auto turns = r.readLinear();
  size_t wrongCount = 0;
  for (size_t i = 3; i < turns.size(); i += 4) wrongCount += turns[i] != 1.0f;
  EXPECT_EQ(wrongCount, 0u);
  EXPECT_EQ(nonFinite(turns), 0u);
  // Under a frame budget a restart traces the share the budget allows: all of it
  // when every frame meets the target, the pattern's 1/16 when none does.
  for (double fps : {0.01, 1000.0}) {
    rs.targetFps = fps;
    rs.rtgi.select = render::RtgiPass::Settings::Select::kMask;
    render::Renderer b(*programs_, room, rs);
    for (int f = 0; f < 40; ++f) b.renderFrame(room.camera);
    b.restartAccumulation();
    b.renderFrame(room.camera);
    EXPECT_DOUBLE_EQ(b.rtgi()->lastTracedFraction(), fps < 1.0 ? 1.0 : 1.0 / 16.0) << fps;
  }
}

// The frame budget moves the traced share between its floor (1/16, an unreachable
// target) and every pixel (a target any frame meets); the mask it selects by
// exists and lies in [0, 1) (at the floor, where it chooses nothing, only when kept
// for display; above it, made again once the budget leaves the floor it starts at);
// the uniform choice traces the same shares.
TEST_F(RtgiTest, FrameBudgetSetsTheTracedShare) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  for (auto select :
       {render::RtgiPass::Settings::Select::kMask, render::RtgiPass::Settings::Select::kUniform}) {
    for (double fps : {1000.0, 0.01}) {
      render::RenderSettings rs = settings(48, 64, render::Mode::kRtgi);
      rs.targetFps = fps;
      rs.rtgi.select = select;
      rs.rtgi.keepMask = fps > 1.0;
      render::Renderer r(*programs_, room, rs);
      for (int f = 0; f < 40; ++f) r.renderFrame();
      const double share = r.rtgi()->lastTracedFraction();
      if (fps > 1.0)
        EXPECT_NEAR(share, 1.0 / 16.0, 0.02) << "fps " << fps;
      else
        EXPECT_GT(share, 0.95) << "fps " << fps;
      const auto px = r.readLinear();
      EXPECT_EQ(nonFinite(px), 0u);
      for (size_t i = 3; i < px.size(); i += 4) ASSERT_GE(px[i], 3.0f);  // every pixel had turns
      if (select == render::RtgiPass::Settings::Select::kMask) {
        const std::vector<float> mask = r.rtgi()->readMask();
        ASSERT_EQ(mask.size(), size_t{48 * 48});
        EXPECT_GE(*std::min_element(mask.begin(), mask.end()), 0.0f);
        EXPECT_LT(*std::max_element(mask.begin(), mask.end()), 1.0f);
        EXPECT_GT(*std::max_element(mask.begin(), mask.end()), 0.0f);
      }
    }
  }
}

// At the budget's floor (the pattern alone traces) no pixel is chosen by the work
// mask, and unless it is kept for display it is not made: no mask stage runs, and
// the image is the same as with the mask made.
TEST_F(RtgiTest, AtTheBudgetsFloorTheMaskIsNotMade) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  std::vector<std::vector<float>> images;
  for (bool keep : {false, true}) {
    render::RenderSettings rs = settings(48, 64, render::Mode::kRtgi);
    rs.targetFps = 1000.0;
    rs.rtgi.select = render::RtgiPass::Settings::Select::kMask;
    rs.rtgi.keepMask = keep;
    render::Renderer r(*programs_, room, rs);
    for (int f = 0; f < 12; ++f) r.renderFrame();
    EXPECT_NEAR(r.rtgi()->lastTracedFraction(), 1.0 / 16.0, 0.02);
    EXPECT_EQ(r.rtgi()->readMask().empty(), !keep);
    images.push_back(r.readLinear());
  }
  EXPECT_EQ(images[0], images[1]);
}

// 10,000 frames of accumulation (8x8 pixels): every pixel holds exactly 10,000
// samples, all finite, and the mean keeps settling: it moves less from frame 1,000
// to 10,000 than from 100 to 1,000 (a float running mean that drifted would not).
TEST_F(RtgiTest, TenThousandFramesStayFiniteAndConverge) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  render::Renderer r(*programs_, room, settings(8, 32, render::Mode::kRtgi));
  std::vector<std::vector<float>> at;
  for (int f = 1; f <= 10000; ++f) {
    r.renderFrame();
    if (f == 100 || f == 1000 || f == 10000) at.push_back(r.readLinear());
  }
  auto rmsChange = [](const std::vector<float>& a, const std::vector<float>& b) {
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i)
      if (i % 4 != 3) sum += (a[i] - b[i]) * (a[i] - b[i]);
    return std::sqrt(sum / static_cast<double>(a.size() / 4 * 3));
  };
  EXPECT_EQ(nonFinite(at[2]), 0u);
  EXPECT_EQ(r.nonfiniteTerms(), 0u);
  for (size_t i = 3; i < at[2].size(); i += 4) ASSERT_EQ(at[2][i], 10000.0f);
  const double early = rmsChange(at[0], at[1]), late = rmsChange(at[1], at[2]);
  std::printf("rtgi 8x8: RMS change 100->1000 frames %.5f, 1000->10000 %.5f (mean %.4f)\n", early,
              late, meanOf(at[2]));
  EXPECT_LT(late, early);
}

// rtgi converges towards the path tracer: its error falls with frames and ends
// within a few per cent of the reference's mean on both reference scenes. Bounds
// from seeds 1-5 (rtgi's, the octree's and the path tracer's seeds all changed):
// cornell_room relative MSE 0.0103-0.0110 (standard deviation 0.0003), mean ratio
// 1.003-1.008; dark_plane 0.0115-0.0415 (fireflies: one seed's 0.0415 against
// 0.012-0.019 for the others; mean 0.021, deviation 0.012), mean ratio 0.997-1.003.
// A blended quad (glTF BLEND) of alpha 0.25, black, 1 m in front of a white plane
// lit along the view (3 lux: radiance 3/pi where lit): the camera's rays and the
// shadow rays pass it with probability 0.75 each, so the image converges to 0.5625
// x 3/pi, as the path tracer's does (PathtraceTest.BlendedSurfacesCoverTheirAlpha).
// Drawn opaque it would be black; ignored, 3/pi. 32 x 32 pixels x 64 frames: the
// mean of 65,536 draws has a standard deviation of 0.2% of it.
TEST_F(RtgiTest, BlendedSurfacesCoverTheirAlpha) {
  test::SceneBuilder b;
  const int plane = b.addMaterial(glm::vec3(1.0f));
  const int glass = b.addMaterial(glm::vec3(0.0f));
  b.scene().materials[static_cast<size_t>(glass)].baseColor.a = 0.25f;
  b.scene().materials[static_cast<size_t>(glass)].alphaMode = scene::AlphaMode::kBlend;
  for (const auto& [z, material] : {std::pair{0.0f, plane}, std::pair{1.0f, glass}})
    b.addTriangles({{-2, -2, z}, {2, -2, z}, {2, 2, z}, {-2, -2, z}, {2, 2, z}, {-2, 2, z}},
                   material);
  scene::Scene s = b.finish();
  test::lightHeadOnFromZ(&s, 3.0f);
  const double lit = 3.0 / 3.14159265358979;
  for (const auto primary :
       {render::RtgiPass::Settings::Primary::kRays, render::RtgiPass::Settings::Primary::kRaster}) {
    render::RenderSettings rs = settings(32, 64, render::Mode::kRtgi);
    rs.rtgi.primary = primary;
    const double mean = meanOf(render(s, rs, 64, s.camera)) / lit;
    std::printf("blended quad of alpha 0.25, primary %s: %.4f of the lit plane (expected 0.5625)\n",
                primary == render::RtgiPass::Settings::Primary::kRays ? "rays" : "raster", mean);
    EXPECT_NEAR(mean, 0.5625, 0.03);
  }
}

TEST_F(RtgiTest, ConvergesTowardsThePathTracer) {
  struct Case {
    std::string path;
    double maxRelMse;
  };
  for (const Case& c : {Case{cornellRoom(), 0.012}, Case{darkPlane(), 0.06}}) {
    const scene::Scene s = scene::loadGltf(c.path);
    const int size = 64;
    const auto reference =
        toImage(render(s, settings(size, 64, render::Mode::kPathtrace), 1, s.camera), size);
    const auto few =
        toImage(render(s, settings(size, 128, render::Mode::kRtgi), 2, s.camera), size);
    const auto many =
        toImage(render(s, settings(size, 128, render::Mode::kRtgi), 64, s.camera), size);
    const image::ErrorMetrics mFew = image::errorMetrics(few, reference);
    const image::ErrorMetrics mMany = image::errorMetrics(many, reference);
    std::printf(
        "%s: rtgi vs pathtrace 256 spp: 2 frames rel MSE %.4f, 64 frames %.4f, mean "
        "ratio %.3f\n",
        c.path.c_str(), mFew.relMse, mMany.relMse, mMany.meanLuminanceRatio);
    EXPECT_LT(mMany.relMse, mFew.relMse);
    EXPECT_LT(mMany.relMse, c.maxRelMse);
    EXPECT_NEAR(mMany.meanLuminanceRatio, 1.0, 0.015);
  }
}

// Where much of what the pixels see has bounced more than once, the light rtgi
// takes from the voxels beyond the pixel's exact first bounce has to be the path
// tracer's, and so has what a rough dielectric floor reflects of it. Two views of
// the validation set, 64x64, 48 frames, against the path tracer at 256 spp with
// paths to depth 64 (at its default 8 it is 1.4% and 1.0% darker here), the mean
// ratio over seeds 1-4 (each within 0.2% of it):
// - the night hall, lit by point lights, its tiled floor (roughness 0.9) seen at a
//   grazing angle: 0.995 (0.985 while the voxels' first estimate was a chain of 6
//   bounces: refinement adds a bounce a cycle, every leaf once, 15 frames here).
//   Against depth 8, 0.983 while the pixel's indirect ray took the floor for Lambert
//   of its base colour, 0.999 with its BSDF drawn.
// - the day hall from its gallery, lit by a 16 x 4 m skylight: 0.988. It was 1.006
//   while the leaves' direct light was taken 1.6 voxels off their centre and a
//   bounce ray read the voxel's albedo: the black skylight panel lies 2 cm under
//   the white plaster that seals the roof, in the same voxels, which sent the
//   floor's light back down (octree_bounce.comp). What is dark now is the skylight's
//   light in the voxels' second bounce, 4% under the path tracer's, its cause not
//   found (docs/measurements.md, leaf-surface-light).
// Bounds: the measured offset and a little over three standard deviations of it.
TEST_F(RtgiTest, TheHallsBouncesAreThePathTracers) {
  struct View {
    const char* name;
    const char* file;
    bool gallery;  // the gallery's viewpoint, else the file's camera
    double tolerance;
  };
  for (const View& v : {View{"night hall", "hall_night.gltf", false, 0.008},
                        View{"day hall, gallery", "hall.gltf", true, 0.015}}) {
    scene::Scene s = scene::loadGltf(sourceDir() + "/scenes/hall/" + v.file);
    if (v.gallery) s.lookAt({9.0f, 5.6f, 5.2f}, {-3.0f, 0.6f, -1.5f});
    const int size = 64;
    // Paths to depth 64, as the references (rtgi's voxels hold every bounce).
    render::RenderSettings pt = settings(size, 128, render::Mode::kPathtrace);
    pt.pathtrace.maxDepth = 64;
    const auto reference = toImage(render(s, pt, 1, s.camera), size);
    double sum = 0.0;
    for (uint32_t seed : {1u, 2u, 3u, 4u}) {
      render::RenderSettings rs = settings(size, 128, render::Mode::kRtgi);
      rs.rtgi.seed = seed;
      rs.octree.seed = seed;
      const auto image = toImage(render(s, rs, 48, s.camera), size);
      const double ratio = image::errorMetrics(image, reference).meanLuminanceRatio;
      std::printf("%s, seed %u: rtgi 48 frames against the path tracer: mean %.4f\n", v.name, seed,
                  ratio);
      sum += ratio;
    }
    EXPECT_NEAR(sum / 4.0, 1.0, v.tolerance) << v.name;
  }
}

// No fixed pattern: two seeds' images differ by noise alone, and that difference
// falls about as 1/sqrt(frames) (4x the frames: about half). Noise baked into the
// voxels' light would stay the same frame after frame.
TEST_F(RtgiTest, SeedsDifferByNoiseThatAverages) {
  const scene::Scene room = scene::loadGltf(cornellRoom());
  render::RenderSettings rs = settings(48, 64, render::Mode::kRtgi);
  auto difference = [&](int frames) {
    rs.rtgi.seed = 1;
    rs.octree.seed = 1;
    const auto a = render(room, rs, frames, room.camera);
    rs.rtgi.seed = 2;
    rs.octree.seed = 2;
    const auto b = render(room, rs, frames, room.camera);
    double d2 = 0.0;
    for (size_t i = 0; i < a.size(); ++i)
      if (i % 4 != 3) d2 += (a[i] - b[i]) * (a[i] - b[i]);
    return std::sqrt(d2 / static_cast<double>(a.size() / 4 * 3)) / meanOf(a);
  };
  const double d16 = difference(16), d64 = difference(64);
  std::printf("two seeds: relative RMS difference %.4f at 16 frames, %.4f at 64 (ratio %.2f)\n",
              d16, d64, d64 / d16);
  EXPECT_LT(d64, 0.65 * d16);
  EXPECT_GT(d64, 0.35 * d16);  // noise that averages, not a difference that vanishes
}

// Antialiasing: a white emitter whose edge crosses the image at 30 degrees, on
// black. With a sub-pixel offset per frame, 256 frames give every pixel its
// box-filtered coverage (the exact area of the pixel on the white side) within 0.02;
// without, the edge stays a staircase of 0s and 1s.
TEST_F(RtgiTest, JitteredEdgeConvergesToTheBoxFilteredCoverage) {
  SceneBuilder b;
  const int white = b.addMaterial(glm::vec3(0.0f), glm::vec3(1.0f));
  // A large quad in z = 0, its edge through the origin at 30 degrees from the x axis.
  const float c = std::cos(0.5235988f), s30 = std::sin(0.5235988f);
  const glm::vec3 along(c, s30, 0.0f), side(-s30, c, 0.0f);
  const glm::vec3 p0 = -4.0f * along, p1 = 4.0f * along;
  b.addTriangles({p0, p1, p1 + 4.0f * side, p0, p1 + 4.0f * side, p0 + 4.0f * side}, white);
  scene::Scene sc = b.finish();
  sc.lights.clear();
  sc.defaultLight = false;
  scene::Camera cam;
  cam.position = glm::vec3(0.0f, 0.0f, 3.0f);
  cam.forward = glm::vec3(0.0f, 0.0f, -1.0f);
  cam.up = glm::vec3(0.0f, 1.0f, 0.0f);
  constexpr int size = 24;
  render::RenderSettings rs = settings(size, 32, render::Mode::kRtgi);
  const auto img = render(sc, rs, 256, cam);
  rs.jitter = false;
  const auto centred = render(sc, rs, 256, cam);
  // The edge in pixels: the image plane at z = 0 spans 2 x 3 tan(20 deg) a side.
  const double half = 3.0 * std::tan(0.3490659), pixel = 2.0 * half / size;
  // Coverage of pixel (x, y) (top-left origin): the area of its square where
  // dot(q, side) > 0, by clipping the square against that half-plane.
  auto coverage = [&](int x, int y) {
    const double x0 = -half + x * pixel, y1 = half - y * pixel;
    std::vector<glm::dvec2> poly = {
        {x0, y1 - pixel}, {x0 + pixel, y1 - pixel}, {x0 + pixel, y1}, {x0, y1}};
    std::vector<glm::dvec2> out;
    const glm::dvec2 n(side.x, side.y);
    for (size_t i = 0; i < poly.size(); ++i) {
      const glm::dvec2 a = poly[i], bb = poly[(i + 1) % poly.size()];
      const double da = glm::dot(a, n), db = glm::dot(bb, n);
      if (da >= 0.0) out.push_back(a);
      if ((da >= 0.0) != (db >= 0.0)) out.push_back(a + (bb - a) * (da / (da - db)));
    }
    double area = 0.0;
    for (size_t i = 0; i < out.size(); ++i) {
      const glm::dvec2 a = out[i], bb = out[(i + 1) % out.size()];
      area += a.x * bb.y - bb.x * a.y;
    }
    return std::abs(area) / 2.0 / (pixel * pixel);
  };
  double worst = 0.0, worstCentred = 0.0;
  int edgePixels = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double cov = coverage(x, y);
      const size_t i = (static_cast<size_t>(y) * size + static_cast<size_t>(x)) * 4;
      worst = std::max(worst, std::abs(img[i] - cov));
      worstCentred = std::max(worstCentred, std::abs(centred[i] - cov));
      edgePixels += cov > 1e-6 && cov < 1.0 - 1e-6;
    }
  std::printf(
      "30-degree edge, %d pixels cut: worst error against the coverage %.4f jittered, "
      "%.4f at pixel centres\n",
      edgePixels, worst, worstCentred);
  EXPECT_GT(edgePixels, size);
  EXPECT_LT(worst, 0.02);
  EXPECT_GT(worstCentred, 0.3);
}

}  // namespace
}  // namespace voxgi::test
