// glTF node animation: sampling, wrapping, motion bounds.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "scene/gltf_loader.h"
#include "support/test_paths.h"

namespace voxgi::scene {
namespace {

std::string movingBox() {
  return test::testDataDir() + "/animated/moving_box.gltf";
}

// World-space x of the centre of the box (the draw of mesh 1).
double boxCenterX(const Scene& s) {
  for (const Draw& d : s.draws) {
    if (d.mesh != 1) continue;
    double lo = 1e30, hi = -1e30;
    for (uint32_t i = d.firstIndex; i < d.firstIndex + d.indexCount; ++i) {
      const double x = s.vertices[s.indices[i]].position.x + s.origin.x;
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    return 0.5 * (lo + hi);
  }
  ADD_FAILURE() << "no box";
  return 0.0;
}

TEST(Animation, LoadsChannelsAndRanges) {
  const Scene s = loadGltf(movingBox());
  EXPECT_TRUE(s.animated());
  ASSERT_EQ(s.animations.size(), 1u);
  EXPECT_EQ(s.animations[0].node, 1);
  EXPECT_DOUBLE_EQ(s.animationDuration, 2.0);
  ASSERT_EQ(s.animatedRanges.size(), 1u);  // the floor does not move
  EXPECT_EQ(s.animatedRanges[0].localPositions.size(), 24u);
}

TEST(Animation, PosesFollowTheKeyframesAndWrap) {
  Scene s = loadGltf(movingBox());
  s.loopAnimation = true;
  EXPECT_NEAR(boxCenterX(s), -0.5, 1e-6);  // loaded at t = 0
  s.pose(1.0);
  EXPECT_NEAR(boxCenterX(s), 0.5, 1e-6);
  s.pose(0.25);
  EXPECT_NEAR(boxCenterX(s), -0.25, 1e-6);
  s.pose(1.5);
  EXPECT_NEAR(boxCenterX(s), 0.0, 1e-6);
  s.pose(2.25);  // wraps to 0.25
  EXPECT_NEAR(boxCenterX(s), -0.25, 1e-6);
  s.pose(0.0);
  EXPECT_NEAR(boxCenterX(s), -0.5, 1e-6);
}

// Without looping (an offline render's default) the last pose stays after the end.
TEST(Animation, TheEndHoldsTheLastPoseUnlessLooping) {
  Scene s = loadGltf(movingBox());
  EXPECT_FALSE(s.loopAnimation);
  s.pose(2.25);
  EXPECT_NEAR(boxCenterX(s), -0.5, 1e-6);  // the key at t = 2
  s.pose(2.0);
  EXPECT_NEAR(boxCenterX(s), -0.5, 1e-6);
  s.pose(-1.0);
  EXPECT_NEAR(boxCenterX(s), -0.5, 1e-6);  // the first key
  s.loopAnimation = true;
  s.pose(2.25);  // wraps to 0.25
  EXPECT_NEAR(boxCenterX(s), -0.25, 1e-6);
  s.pose(-0.25);  // wraps to 1.75
  EXPECT_NEAR(boxCenterX(s), -0.25, 1e-6);
}

// A path whose last key is at 29/30 s, stored as a float, a hair below the double
// 29/30 at which frame 29 of a 30 fps render is asked for: that frame is at the last
// key, looping or not (it wrapped to the first pose when the times were compared in
// double precision).
TEST(Animation, AFrameTimeAHairPastAFloatKeyIsAtThatKey) {
  Scene s = loadGltf(movingBox());
  AnimationChannel& c = s.animations[0];
  c.times = {0.0f, 0.5f, static_cast<float>(29.0 / 30.0)};
  c.values.back() = glm::dvec4(1.5, 0.0, 0.0, 0.0);
  s.animationDuration = c.times.back();
  ASSERT_GT(29.0 / 30.0, s.animationDuration);
  for (bool loop : {false, true}) {
    SCOPED_TRACE(loop ? "looping" : "held");
    s.loopAnimation = loop;
    s.pose(29.0 / 30.0);
    EXPECT_NEAR(boxCenterX(s), 1.5, 1e-6);
    s.pose(28.0 / 30.0);
    EXPECT_NEAR(boxCenterX(s), 0.5 + (28.0 / 30.0 - 0.5) / (29.0 / 30.0 - 0.5), 1e-5);
  }
}

// World-space half-width in x of the box (the draw of mesh 1).
double boxHalfWidthX(const Scene& s) {
  for (const Draw& d : s.draws) {
    if (d.mesh != 1) continue;
    double lo = 1e30, hi = -1e30;
    for (uint32_t i = d.firstIndex; i < d.firstIndex + d.indexCount; ++i) {
      lo = std::min(lo, static_cast<double>(s.vertices[s.indices[i]].position.x));
      hi = std::max(hi, static_cast<double>(s.vertices[s.indices[i]].position.x));
    }
    return 0.5 * (hi - lo);
  }
  ADD_FAILURE() << "no box";
  return 0.0;
}

// glTF's cubic Hermite spline (Appendix C) over one interval of `span` seconds.
double hermite(double p0, double out0, double p1, double in1, double span, double u) {
  const double u2 = u * u, u3 = u2 * u;
  return (2 * u3 - 3 * u2 + 1) * p0 + span * (u3 - 2 * u2 + u) * out0 + (-2 * u3 + 3 * u2) * p1 +
         span * (u3 - u2) * in1;
}

TEST(Animation, CubicSplineFollowsTheHermiteBasisWithTheFilesTangents) {
  // The box's x: keys -0.5 (out-tangent 1 per second) and 0.5 (in-tangent 0), 2 s
  // apart; its rotation about y: 0 to 90 degrees, zero tangents.
  Scene s = loadGltf(test::testDataDir() + "/animated/cubic_box.gltf");
  ASSERT_EQ(s.animations.size(), 2u);
  EXPECT_EQ(s.animations[0].interpolation, Interpolation::kCubicSpline);
  ASSERT_EQ(s.animations[0].inTangents.size(), 2u);
  EXPECT_DOUBLE_EQ(s.animations[0].outTangents[0].x, 1.0);
  for (double t : {0.0, 0.5, 1.0, 1.5, 1.9}) {  // 2.0 wraps to 0
    s.pose(t);
    const double u = t / 2.0;
    EXPECT_NEAR(boxCenterX(s), hermite(-0.5, 1.0, 0.5, 0.0, 2.0, u), 1e-5) << "t " << t;
    // The quaternion (0, sin, 0, cos) of 45 degrees weighed by h01 against the
    // identity weighed by h00, normalized: the angle about y it turns the box by.
    const double h00 = hermite(1, 0, 0, 0, 2, u), h01 = hermite(0, 0, 1, 0, 2, u);
    const double angle = 2.0 * std::atan2(h01 * 0.7071068, h00 + h01 * 0.7071068);
    EXPECT_NEAR(boxHalfWidthX(s), 0.25 * (std::cos(angle) + std::sin(angle)), 1e-5) << "t " << t;
  }
  // Not the straight line: a quarter of the way the spline has left the keys'
  // chord (-0.0625 against -0.25) and turned less than a slerp (13.2 against 22.5
  // degrees).
  s.pose(0.5);
  EXPECT_NEAR(boxCenterX(s), -0.0625, 1e-5);
  EXPECT_NEAR(boxHalfWidthX(s), 0.25 * (std::cos(0.2305) + std::sin(0.2305)), 2e-4);
}

TEST(Animation, BoundsCoverEveryPose) {
  const Scene s = loadGltf(movingBox());
  // The box spans x in [-0.75, 0.75] over the animation, y up to 0.5.
  EXPECT_LE(s.motionBounds.min.x + s.origin.x, -0.75 + 1e-5);
  EXPECT_GE(s.motionBounds.max.x + s.origin.x, 0.75 - 1e-5);
  EXPECT_GE(s.bounds.max.y + s.origin.y, 0.5 - 1e-5);
}

TEST(Animation, StaticScenesHaveNone) {
  Scene s = loadGltf(test::cornellRoom());
  EXPECT_FALSE(s.animated());
  const auto before = s.vertices[0].position;
  s.pose(1.0);  // a no-op
  EXPECT_EQ(s.vertices[0].position, before);
}

}  // namespace
}  // namespace voxgi::scene
