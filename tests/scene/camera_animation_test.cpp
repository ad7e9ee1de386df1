// glTF camera and light animation: the camera and KHR_lights_punctual lights follow
// their nodes' channels through the hierarchy (tests/data/animated/camera_path.gltf,
// written by make_camera_path.py, whose numbers the expectations below are computed
// from by hand).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/log.h"
#include "scene/gltf_loader.h"
#include "support/test_paths.h"

namespace voxgi::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string cameraPath() {
  return test::testDataDir() + "/animated/camera_path.gltf";
}

glm::dvec3 world(const Scene& s, const glm::vec3& p) {
  return glm::dvec3(p) + s.origin;
}

// The hand-computed path: the dolly slides x from -1 to 1 over 2 s at y 1, z 3.5;
// the camera sits 0.2 above it, pitched 15 degrees down, and turns from a yaw of
// -20 to +20 degrees about +y. The two rotation keys differ by a yaw of 40
// degrees, so their slerp is the pitch turned by a yaw linear in t:
// forward = R_y(yaw) (0, -sin 15, -cos 15), up = R_y(yaw) (0, cos 15, -sin 15).
constexpr double kPitch = 15.0 * kPi / 180.0;
double expectedYaw(double t) {
  return (-20.0 + 20.0 * t) * kPi / 180.0;
}
glm::dvec3 expectedPosition(double t) {
  return {-1.0 + t, 1.2, 3.5};
}
glm::dvec3 expectedForward(double t) {
  const double a = expectedYaw(t);
  return {-std::cos(kPitch) * std::sin(a), -std::sin(kPitch), -std::cos(kPitch) * std::cos(a)};
}
glm::dvec3 expectedUp(double t) {
  const double a = expectedYaw(t);
  return {-std::sin(kPitch) * std::sin(a), std::cos(kPitch), -std::sin(kPitch) * std::cos(a)};
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tol, const char* what) {
  EXPECT_NEAR(a.x, b.x, tol) << what;
  EXPECT_NEAR(a.y, b.y, tol) << what;
  EXPECT_NEAR(a.z, b.z, tol) << what;
}

void expectCameraAt(const Scene& s, double t) {
  SCOPED_TRACE(testing::Message() << "t = " << t);
  expectNear(world(s, s.camera.position), expectedPosition(t), 1e-5, "position");
  expectNear(glm::dvec3(s.camera.forward), expectedForward(t), 1e-5, "forward");
  expectNear(glm::dvec3(s.camera.up), expectedUp(t), 1e-5, "up");
}

TEST(CameraAnimation, LoadsThePathAndTheMovingLights) {
  const Scene s = loadGltf(cameraPath());
  EXPECT_TRUE(s.animated());
  EXPECT_FALSE(s.meshesAnimated());  // the room and the block stay
  EXPECT_TRUE(s.cameraMoves);
  EXPECT_TRUE(s.camera.fromFile);
  EXPECT_EQ(s.camera.node, 3);
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].node, 4);
  EXPECT_EQ(s.lights[1].node, 5);
  EXPECT_TRUE(s.lights[0].moves);
  EXPECT_TRUE(s.lights[1].moves);
  EXPECT_TRUE(s.lightsAnimated());
  EXPECT_DOUBLE_EQ(s.animationDuration, 2.0);
  EXPECT_TRUE(s.warnings.empty());
  // Loaded at t = 0.
  expectCameraAt(s, 0.0);
}

TEST(CameraAnimation, ParentedCameraFollowsTheInterpolation) {
  Scene s = loadGltf(cameraPath());
  for (double t : {0.5, 1.0, 1.5, 0.25, 1.999, 0.0}) {
    s.pose(t);
    expectCameraAt(s, t);
  }
  // The rotation is a slerp: at t = 0.5 the yaw is -10 degrees (a quarter of the
  // way), looking right of -z and 15 degrees down: forward
  // (cos 15 sin 10, -sin 15, -cos 15 cos 10). A plain lerp of the keys would give
  // the same direction only after renormalising, and a level camera never.
  s.pose(0.5);
  const double c15 = std::cos(kPitch), d10 = 10.0 * kPi / 180.0;
  EXPECT_NEAR(s.camera.forward.x, c15 * std::sin(d10), 1e-6);
  EXPECT_NEAR(s.camera.forward.y, -std::sin(kPitch), 1e-6);
  EXPECT_NEAR(s.camera.forward.z, -c15 * std::cos(d10), 1e-6);
  EXPECT_NEAR(glm::length(s.camera.forward), 1.0f, 1e-6);
  EXPECT_NEAR(glm::dot(s.camera.forward, s.camera.up), 0.0f, 1e-6);
  // After the 2 s animation the last pose stays (before it, the first); looping,
  // time wraps around it (t = 2 itself is the end).
  s.pose(2.5);
  expectCameraAt(s, 2.0);
  s.pose(-0.5);
  expectCameraAt(s, 0.0);
  s.loopAnimation = true;
  s.pose(2.0);
  expectCameraAt(s, 2.0);
  s.pose(2.5);
  expectCameraAt(s, 0.5);
  s.pose(-0.5);
  expectCameraAt(s, 1.5);
}

TEST(CameraAnimation, ClipPlanesFollowTheCamera) {
  Scene s = loadGltf(cameraPath());
  for (double t : {0.0, 0.7, 1.9}) {
    s.pose(t);
    Camera fitted = s.camera;
    fitClipPlanes(&fitted, s.bounds);
    EXPECT_EQ(s.camera.znear, fitted.znear) << t;
    EXPECT_EQ(s.camera.zfar, fitted.zfar) << t;
    EXPECT_GT(s.camera.znear, 0.0f);
  }
}

TEST(CameraAnimation, LightsMove) {
  Scene s = loadGltf(cameraPath());
  const Light& lamp = s.lights[0];
  const Light& sun = s.lights[1];
  // The lamp slides x from -1.2 to 1.2 over 2 s at y 0.3, z 0.8 (LINEAR).
  for (double t : {0.0, 0.5, 1.0, 1.75}) {
    s.pose(t);
    expectNear(world(s, lamp.position), {-1.2 + 1.2 * t, 0.3, 0.8}, 1e-5, "lamp");
  }
  // The sun (STEP) shines straight down until t = 1, then tilted 30 degrees to -z.
  s.pose(0.5);
  expectNear(glm::dvec3(sun.direction), {0.0, -1.0, 0.0}, 1e-6, "sun before 1 s");
  s.pose(0.999);
  expectNear(glm::dvec3(sun.direction), {0.0, -1.0, 0.0}, 1e-6, "sun just before 1 s");
  s.pose(1.0);
  expectNear(glm::dvec3(sun.direction), {0.0, -std::cos(kPi / 6), -0.5}, 1e-6, "sun at 1 s");
  s.pose(1.5);
  expectNear(glm::dvec3(sun.direction), {0.0, -std::cos(kPi / 6), -0.5}, 1e-6, "sun after 1 s");
  // The camera's options leave the lights alone, and the geometry stays.
  const std::vector<Vertex> before = s.vertices;
  s.poseCamera = false;
  const Camera held = s.camera;
  s.pose(0.25);
  EXPECT_EQ(s.camera.position, held.position);
  EXPECT_EQ(s.camera.forward, held.forward);
  expectNear(world(s, lamp.position), {-1.2 + 0.3, 0.3, 0.8}, 1e-5, "lamp with a held camera");
  ASSERT_EQ(s.vertices.size(), before.size());
  for (size_t i = 0; i < before.size(); ++i)
    ASSERT_EQ(s.vertices[i].position, before[i].position) << i;
}

TEST(CameraAnimation, StaticCamerasAndLightsStay) {
  // A still scene: nothing moves at all.
  Scene still = loadGltf(test::cornellRoom());
  EXPECT_FALSE(still.cameraMoves);
  EXPECT_FALSE(still.lightsAnimated());
  const Camera c = still.camera;
  std::vector<glm::vec3> lights;
  for (const Light& l : still.lights) lights.push_back(l.position);
  still.pose(0.7);
  EXPECT_EQ(still.camera.position, c.position);
  EXPECT_EQ(still.camera.forward, c.forward);
  EXPECT_EQ(still.camera.znear, c.znear);
  for (size_t i = 0; i < lights.size(); ++i) EXPECT_EQ(still.lights[i].position, lights[i]);
  // Meshes move, the camera does not: moving_box's camera is not animated.
  Scene box = loadGltf(test::testDataDir() + "/animated/moving_box.gltf");
  EXPECT_TRUE(box.animated());
  EXPECT_FALSE(box.cameraMoves);
  const Camera bc = box.camera;
  box.pose(1.3);
  EXPECT_EQ(box.camera.position, bc.position);
  EXPECT_EQ(box.camera.forward, bc.forward);
  EXPECT_EQ(box.camera.zfar, bc.zfar);
}

// --- malformed channels on the camera's node: one line, naming the problem --------

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// What loading the camera path with `edit` applied says ("" when it loads).
std::string errorWith(const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json g = nlohmann::json::parse(readText(cameraPath()));
  edit(g);
  const std::string text = g.dump();
  try {
    loadGltfFromMemory(text.data(), text.size(), "camera_path.gltf");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

void expectOneLineError(const std::string& what, const std::string& substring) {
  EXPECT_NE(what.find(substring), std::string::npos) << "got: " << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  EXPECT_EQ(what.rfind("camera_path.gltf: ", 0), 0u) << what;
}

TEST(CameraAnimation, MalformedCameraChannelsAreRefused) {
  // Channel 1 turns the camera (node 3) with sampler 1.
  EXPECT_EQ(errorWith([](nlohmann::json&) {}), "");
  // Fewer rotation keys than times.
  expectOneLineError(errorWith([](nlohmann::json& g) {
                       const int out = g["animations"][0]["samplers"][1]["output"];
                       g["accessors"][out]["count"] = 1;
                     }),
                     "animation 0 channel 1: input and output counts differ");
  // A rotation read from the translation keys (VEC3).
  expectOneLineError(errorWith([](nlohmann::json& g) {
                       g["animations"][0]["samplers"][1]["output"] =
                           g["animations"][0]["samplers"][0]["output"];
                     }),
                     "(animation output): element type");
  // A sampler that does not exist.
  expectOneLineError(
      errorWith([](nlohmann::json& g) { g["animations"][0]["channels"][1]["sampler"] = 7; }),
      "animation 0 channel 1: sampler 7 does not exist");
  // Key times from an accessor that does not exist.
  expectOneLineError(
      errorWith([](nlohmann::json& g) { g["animations"][0]["samplers"][1]["input"] = 99; }),
      "animation input: accessor 99 points nowhere");
  // A camera node given by a matrix cannot be animated.
  expectOneLineError(errorWith([](nlohmann::json& g) {
                       nlohmann::json& cam = g["nodes"][3];
                       cam.erase("translation");
                       cam.erase("rotation");
                       cam["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0.2, 0, 1};
                     }),
                     "animation 0 channel 1: node 3 has a matrix and cannot be animated");
}

}  // namespace
}  // namespace voxgi::scene
