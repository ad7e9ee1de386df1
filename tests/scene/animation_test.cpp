// glTF node animation: sampling, wrapping, motion bounds.
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
