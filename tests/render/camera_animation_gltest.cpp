// Camera paths and moving lights on the GPU (tests/data/animated/camera_path.gltf):
// the animated camera renders what a hand-placed camera at its pose renders, in
// raster and pathtrace; a moving lamp moves its bright spot; a moved light
// re-lights the voxels (rtgi matches a fresh render of the new pose); still scenes
// are unaffected; `voxgi render --frames --fps` plays the path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string cameraPath() {
  return testDataDir() + "/animated/camera_path.gltf";
}

render::RenderSettings settings(render::Mode mode, int w, int h) {
  render::RenderSettings s;
  s.mode = mode;
  s.width = w;
  s.height = h;
  s.voxels = 64;
  return s;
}

// The path's camera at time t, placed by hand (make_camera_path.py's numbers).
scene::Camera handCamera(const scene::Scene& s, double t) {
  scene::Camera c = s.camera;
  const double a = (-20.0 + 20.0 * t) * kPi / 180.0, p = 15.0 * kPi / 180.0;
  c.position = glm::vec3(glm::dvec3(-1.0 + t, 1.2, 3.5) - s.origin);
  c.forward = glm::vec3(-std::cos(p) * std::sin(a), -std::sin(p), -std::cos(p) * std::cos(a));
  c.up = glm::vec3(-std::sin(p) * std::sin(a), std::cos(p), -std::sin(p) * std::cos(a));
  scene::fitClipPlanes(&c, s.bounds);
  return c;
}

// Mean absolute difference over all channels.
double meanDifference(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += std::abs(static_cast<double>(a[i]) - b[i]);
  return a.empty() ? 0.0 : sum / static_cast<double>(a.size());
}
double meanValue(const std::vector<float>& a) {
  double sum = 0.0;
  for (float v : a) sum += std::abs(static_cast<double>(v));
  return a.empty() ? 0.0 : sum / static_cast<double>(a.size());
}

class CameraAnimationTest : public GlProgramsTest {};

TEST_F(CameraAnimationTest, PathCameraRendersAsTheHandPlacedOne) {
  for (render::Mode mode : {render::Mode::kRaster, render::Mode::kPathtrace}) {
    SCOPED_TRACE(render::modeName(mode));
    scene::Scene s = scene::loadGltf(cameraPath());
    render::RenderSettings rs = settings(mode, 48, 40);
    rs.spp = 2;
    render::Renderer r(*programs_, s, rs);
    r.renderFrame();
    const auto first = r.readLinear();
    s.pose(1.5);
    r.posed();
    r.renderFrame();
    const auto path = r.readLinear();
    EXPECT_GT(meanDifference(first, path), 0.05 * meanValue(first));  // the view moved
    // The same frame from the hand-placed camera (the lights at 1.5 s too).
    s.poseCamera = false;
    s.camera = handCamera(s, 1.5);
    r.renderFrame();
    const auto hand = r.readLinear();
    // Float rounding of the two cameras' bases differs: raster agrees to far below
    // 1e-3, pathtrace's paths to its noise at edges.
    EXPECT_LT(meanDifference(path, hand),
              (mode == render::Mode::kRaster ? 1e-3 : 2e-2) * meanValue(hand));
  }
}

// Where the lamp's bright spot lies: the centroid of the pixels above half the
// brightest, in pixels.
glm::dvec2 brightSpot(const std::vector<float>& rgba, int w, int h) {
  float top = 0.0f;
  for (size_t i = 0; i < rgba.size(); i += 4) top = std::max(top, rgba[i + 1]);
  glm::dvec2 sum(0.0);
  double n = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float g =
          rgba[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 4 + 1];
      if (g < 0.5f * top) continue;
      sum += glm::dvec2(x + 0.5, y + 0.5);
      n += 1.0;
    }
  return n > 0.0 ? sum / n : glm::dvec2(-1.0);
}

TEST_F(CameraAnimationTest, BrightSpotMovesWithTheLamp) {
  scene::Scene s = scene::loadGltf(cameraPath());
  // Looking straight down on the floor from above the open room: image right is +x.
  s.poseCamera = false;
  s.camera.position = glm::vec3(glm::dvec3(0.0, 4.0, 0.8) - s.origin);
  s.camera.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  s.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
  s.fitClipPlanes();
  const int w = 64, h = 64;
  render::Renderer r(*programs_, s, settings(render::Mode::kRaster, w, h));
  for (double t : {0.25, 1.0, 1.75}) {
    SCOPED_TRACE(testing::Message() << "t = " << t);
    s.pose(t);
    r.posed();
    r.renderFrame();
    const glm::dvec2 spot = brightSpot(r.readLinear(), w, h);
    // The floor under the lamp, projected (rows top-down, as read back).
    const glm::vec3 under = glm::vec3(glm::dvec3(-1.2 + 1.2 * t, 0.0, 0.8) - s.origin);
    const glm::vec4 clip = s.camera.projection(1.0f) * s.camera.view() * glm::vec4(under, 1.0f);
    const glm::dvec2 expected((clip.x / clip.w * 0.5 + 0.5) * w, (0.5 - clip.y / clip.w * 0.5) * h);
    EXPECT_NEAR(spot.x, expected.x, 2.0);
    EXPECT_NEAR(spot.y, expected.y, 2.0);
  }
}

TEST_F(CameraAnimationTest, MovedLightRelightsTheVoxels) {
  // rtgi from a held camera: after the lamp moves, the voxel light is injected again
  // and the first frame equals that of a renderer made for the new pose.
  scene::Scene s = scene::loadGltf(cameraPath());
  s.poseCamera = false;
  render::RenderSettings rs = settings(render::Mode::kRtgi, 40, 32);
  rs.jitter = false;
  render::Renderer r(*programs_, s, rs);
  r.renderFrame();
  const std::vector<glm::vec4> lightBefore = r.octree()->readMean();
  for (int i = 0; i < 2; ++i) r.renderFrame();
  EXPECT_EQ(r.accumulatedFrames(), 3);
  s.pose(1.5);
  r.posed();
  EXPECT_EQ(r.accumulatedFrames(), 0);
  r.renderFrame();
  bool injected = false;
  for (const gl::StageTime& st : r.lastStages()) injected = injected || st.stage == Stage::kInject;
  EXPECT_TRUE(injected);
  const auto moved = r.readLinear();
  const std::vector<glm::vec4> lightAfter = r.octree()->readMean();
  render::Renderer fresh(*programs_, s, rs);
  fresh.renderFrame();
  const auto expected = fresh.readLinear();
  EXPECT_LT(meanDifference(moved, expected), 0.02 * meanValue(expected));
  // The voxels' light moved with the lamp (the same octree: node by node), and is
  // that of the new pose: the fresh renderer's first estimate (its own octree, whose
  // nodes may be numbered otherwise: compared as sorted values).
  const std::vector<glm::vec4> lightFresh = fresh.octree()->readMean();
  ASSERT_EQ(lightBefore.size(), lightAfter.size());
  auto luminance = [](const std::vector<glm::vec4>& v) {
    std::vector<float> out;
    for (const glm::vec4& x : v) out.push_back(x.r + x.g + x.b);
    return out;
  };
  EXPECT_GT(meanDifference(luminance(lightBefore), luminance(lightAfter)),
            0.1 * meanValue(luminance(lightAfter)));
  std::vector<float> after = luminance(lightAfter), fresh1 = luminance(lightFresh);
  std::sort(after.begin(), after.end());
  std::sort(fresh1.begin(), fresh1.end());
  ASSERT_EQ(after.size(), fresh1.size());
  EXPECT_LT(meanDifference(after, fresh1), 0.02 * meanValue(fresh1));
  // The next frame refines, as for a still scene.
  r.renderFrame();
  injected = false;
  for (const gl::StageTime& st : r.lastStages()) injected = injected || st.stage == Stage::kInject;
  EXPECT_FALSE(injected);
  EXPECT_EQ(r.accumulatedFrames(), 2);
}

TEST_F(CameraAnimationTest, StillScenesAreUnaffected) {
  scene::Scene s = scene::loadGltf(cornellRoom());
  render::Renderer r(*programs_, s, settings(render::Mode::kRaster, 32, 32));
  r.renderFrame();
  const auto before = r.readLinear();
  s.pose(0.8);
  r.posed();
  r.renderFrame();
  EXPECT_EQ(r.readLinear(), before);
  EXPECT_EQ(r.accumulatedFrames(), 2);  // nothing moved: accumulation goes on
}

TEST(CameraAnimationCli, RenderPlaysTheCameraPath) {
  // Frame 15 at 10 fps shows t = 1.5: the same image as --time 1.5 alone.
  const std::string dir = scratchDir();
  const std::string common =
      voxgiBinary() + " render " + cameraPath() + " --mode raster --size 48x40 --quiet ";
  CommandResult r = runCommand(common + "--frames 16 --fps 10 --out " + dir +
                               "/played.png --stats " + dir + "/played.json");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = runCommand(common + "--time 1.5 --out " + dir + "/posed.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = runCommand(common + "--out " + dir + "/first.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const image::Image played = image::readImage(dir + "/played.png");
  const image::Image posed = image::readImage(dir + "/posed.png");
  const image::Image first = image::readImage(dir + "/first.png");
  EXPECT_EQ(played.pixels, posed.pixels);
  EXPECT_NE(played.pixels, first.pixels);
  const nlohmann::json stats = nlohmann::json::parse([&] {
    std::ifstream in(dir + "/played.json");
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }());
  EXPECT_EQ(stats["animated"], true);
  EXPECT_EQ(stats["camera_path"], true);
  EXPECT_EQ(stats["moving_lights"], 2);
  // --look-from holds the viewpoint: the lights still move, so frame 15 differs
  // from the first frame from there, and equals --time 1.5 from there.
  const std::string look = "--look-from 0,1.5,3.5 --look-at 0,0.5,0 ";
  ASSERT_EQ(runCommand(common + look + "--frames 16 --fps 10 --out " + dir + "/lp.png").exitCode,
            0);
  ASSERT_EQ(runCommand(common + look + "--time 1.5 --out " + dir + "/lt.png").exitCode, 0);
  ASSERT_EQ(runCommand(common + look + "--out " + dir + "/l0.png").exitCode, 0);
  EXPECT_EQ(image::readImage(dir + "/lp.png").pixels, image::readImage(dir + "/lt.png").pixels);
  EXPECT_NE(image::readImage(dir + "/lp.png").pixels, image::readImage(dir + "/l0.png").pixels);
}

// Frames after the path's end (2 s) hold its last pose; --loop wraps them around.
TEST(CameraAnimationCli, TheLastFrameHoldsTheLastKey) {
  const std::string dir = scratchDir();
  const std::string common =
      voxgiBinary() + " render " + cameraPath() + " --mode raster --size 48x40 --quiet ";
  const auto render = [&](const std::string& args, const std::string& name) {
    const CommandResult r = runCommand(common + args + " --out " + dir + "/" + name + ".png");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return image::readImage(dir + "/" + name + ".png").pixels;
  };
  const auto last = render("--time 2", "last");
  EXPECT_NE(last, render("", "first"));
  EXPECT_EQ(render("--frames 21 --fps 10", "end"), last);  // frame 20 at t = 2
  EXPECT_EQ(render("--frames 26 --fps 10", "after"), last);
  EXPECT_EQ(render("--frames 26 --fps 10 --loop", "looped"), render("--time 0.5", "half"));
}

}  // namespace
}  // namespace voxgi::test
