// The viewer's fly camera without GL: untouched it is exactly the start camera;
// moves scale with the scene's speed and time; turning keeps up and clamps pitch.
#include "app/fly_camera.h"

#include <gtest/gtest.h>

#include <cmath>

namespace voxgi::app {
namespace {

scene::Camera startCamera() {
  scene::Camera c;
  c.position = {0.0f, 1.0f, 5.0f};
  c.forward = {0.0f, 0.0f, -1.0f};
  c.up = {0.0f, 1.0f, 0.0f};
  c.znear = 0.1f;
  c.zfar = 50.0f;
  return c;
}

scene::Bounds unitBox() {
  scene::Bounds b;
  b.extend({-1.0f, -1.0f, -1.0f});
  b.extend({1.0f, 1.0f, 1.0f});
  return b;
}

void expectNear(const glm::vec3& a, const glm::vec3& b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(FlyCamera, UntouchedIsExactlyTheStartCamera) {
  FlyCamera fly(startCamera(), unitBox(), 2.0f);
  EXPECT_FALSE(fly.update({}, 0.5f));
  const scene::Camera& c = fly.camera();
  EXPECT_EQ(c.position, startCamera().position);
  EXPECT_EQ(c.forward, startCamera().forward);
  EXPECT_EQ(c.znear, startCamera().znear);  // clip planes untouched until it moves
  EXPECT_EQ(c.zfar, startCamera().zfar);
}

TEST(FlyCamera, MovesAtSpeedTimesTime) {
  FlyCamera fly(startCamera(), unitBox(), 2.0f);
  FlyInput in;
  in.move = {0.0f, 0.0f, 1.0f};  // W
  EXPECT_TRUE(fly.update(in, 0.5f));
  expectNear(fly.camera().position, {0.0f, 1.0f, 4.0f});  // 2 units/s for 0.5 s along -z
  in.move = {1.0f, 0.0f, 0.0f};                           // D: right is +x looking down -z
  fly.update(in, 0.25f);
  expectNear(fly.camera().position, {0.5f, 1.0f, 4.0f});
  in.move = {0.0f, -1.0f, 0.0f};  // Q: down along up
  in.speedScale = 4.0f;
  fly.update(in, 0.25f);
  expectNear(fly.camera().position, {0.5f, -1.0f, 4.0f});
}

TEST(FlyCamera, MovingRefitsClipPlanes) {
  FlyCamera fly(startCamera(), unitBox(), 100.0f);
  FlyInput in;
  in.move = {0.0f, 0.0f, -1.0f};  // S: back, far away from the box
  fly.update(in, 1.0f);
  const scene::Camera& c = fly.camera();
  EXPECT_NEAR(c.position.z, 105.0f, 1e-3f);
  // The far plane still reaches past the box; the near plane stays in front of it.
  EXPECT_GT(c.zfar, 106.0f);
  EXPECT_LT(c.znear, 104.0f);
  EXPECT_GT(c.znear, 0.0f);
}

TEST(FlyCamera, YawTurnsAboutUp) {
  FlyCamera fly(startCamera(), unitBox(), 1.0f);
  FlyInput in;
  // Mouse right by a quarter turn's worth of pixels turns right: -z becomes +x.
  in.look = {static_cast<float>(M_PI / 2.0) / FlyCamera::kRadiansPerPixel, 0.0f};
  fly.update(in, 0.0f);
  expectNear(fly.camera().forward, {1.0f, 0.0f, 0.0f}, 1e-4f);
  expectNear(fly.camera().up, {0.0f, 1.0f, 0.0f});
  EXPECT_EQ(fly.camera().position, startCamera().position);  // turning does not move
}

TEST(FlyCamera, PitchIsClampedShortOfThePoles) {
  FlyCamera fly(startCamera(), unitBox(), 1.0f);
  FlyInput in;
  in.look = {0.0f, -10000.0f};  // mouse far up: look up, but never straight up
  fly.update(in, 0.0f);
  EXPECT_NEAR(fly.pitch(), FlyCamera::kMaxPitch, 1e-4f);
  EXPECT_NEAR(glm::length(fly.camera().forward), 1.0f, 1e-5f);
  in.look = {0.0f, 20000.0f};
  fly.update(in, 0.0f);
  EXPECT_NEAR(fly.pitch(), -FlyCamera::kMaxPitch, 1e-4f);
  // Yaw still works at the clamp (the right vector is well defined there).
  in.look = {100.0f, 0.0f};
  fly.update(in, 0.0f);
  EXPECT_NEAR(fly.pitch(), -FlyCamera::kMaxPitch, 1e-4f);
}

TEST(FlyCamera, TiltedUpIsKept) {
  scene::Camera c = startCamera();
  c.forward = {1.0f, 0.0f, 0.0f};
  c.up = {0.0f, 0.0f, 1.0f};  // a z-up file
  FlyCamera fly(c, unitBox(), 1.0f);
  FlyInput in;
  in.move = {0.0f, 1.0f, 0.0f};  // E goes along the file's up
  fly.update(in, 1.0f);
  expectNear(fly.camera().position, c.position + glm::vec3(0.0f, 0.0f, 1.0f));
  in = {};
  in.look = {0.0f, -0.3f / FlyCamera::kRadiansPerPixel};  // look up by 0.3 rad
  fly.update(in, 0.0f);
  EXPECT_NEAR(fly.pitch(), 0.3f, 1e-4f);
  EXPECT_NEAR(fly.camera().forward.z, std::sin(0.3f), 1e-4f);
}

TEST(FlyCamera, ResetReturnsToTheStart) {
  FlyCamera fly(startCamera(), unitBox(), 1.0f);
  FlyInput in;
  in.move = {1.0f, 1.0f, 1.0f};
  in.look = {30.0f, 40.0f};
  fly.update(in, 0.1f);
  EXPECT_NE(fly.camera().position, startCamera().position);
  fly.reset();
  EXPECT_EQ(fly.camera().position, startCamera().position);
  EXPECT_EQ(fly.camera().forward, startCamera().forward);
  EXPECT_EQ(fly.camera().zfar, startCamera().zfar);
}

TEST(FlyCamera, SpeedFromSceneBoundsCrossesInSeconds) {
  // Scene::finalize sets cameraSpeed from the bounds: a quarter of the diagonal per
  // second, whatever the unit.
  for (float size : {0.01f, 1.0f, 1000.0f}) {
    scene::Scene s;
    s.vertices.push_back({{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, {}});
    s.vertices.push_back({{size, size, size}, {0.0f, 0.0f, 1.0f}, {}});
    s.finalize();
    FlyCamera fly(s.camera, s.bounds, s.scale.cameraSpeed);
    FlyInput in;
    in.move = {0.0f, 0.0f, 1.0f};
    const glm::vec3 before = fly.camera().position;
    fly.update(in, 4.0f);
    EXPECT_NEAR(glm::length(fly.camera().position - before), s.bounds.diagonal(),
                1e-4f * s.bounds.diagonal());
  }
}

}  // namespace
}  // namespace voxgi::app
