// Re-voxelizing an animated scene every frame gives, at each pose, exactly the grid
// a fresh voxelization of that pose gives: nothing of earlier poses is left behind.
#include <gtest/gtest.h>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

class RevoxelizeTest : public GlTest {};

scene::Scene movingBox() {
  return scene::loadGltf(testDataDir() + "/animated/moving_box.gltf");
}

// Voxels as cubes, 64^3, on a 32x32 image.
render::RenderSettings pointsSettings(bool revoxelize) {
  render::RenderSettings rs;
  rs.width = rs.height = 32;
  rs.mode = render::Mode::kPoints;
  rs.voxels = 64;
  rs.revoxelize = revoxelize;
  return rs;
}

uint64_t freshChecksum(double t) {
  scene::Scene s = movingBox();
  s.pose(t);
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::Renderer r(programs, s, pointsSettings(false));
  r.renderFrame();
  return r.voxelGrid()->stats().checksum;
}

TEST_F(RevoxelizeTest, EveryPoseMatchesAFreshVoxelization) {
  scene::Scene s = movingBox();
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::Renderer r(programs, s, pointsSettings(true));
  std::vector<uint64_t> seen;
  for (double t : {0.0, 0.4, 1.0, 1.7, 0.0}) {
    s.pose(t);
    r.geometryChanged();
    r.renderFrame();
    const uint64_t sum = r.voxelGrid()->stats().checksum;
    EXPECT_EQ(sum, freshChecksum(t)) << "t = " << t;
    seen.push_back(sum);
  }
  EXPECT_NE(seen[0], seen[2]);  // the box moved
  EXPECT_EQ(seen[0], seen[4]);  // and came back
}

TEST_F(RevoxelizeTest, WithoutRevoxelizeTheGridStays) {
  scene::Scene s = movingBox();
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::Renderer r(programs, s, pointsSettings(false));
  r.renderFrame();
  const uint64_t first = r.voxelGrid()->stats().checksum;
  s.pose(1.0);
  r.geometryChanged();
  r.renderFrame();
  EXPECT_EQ(r.voxelGrid()->stats().checksum, first);
}

}  // namespace
}  // namespace voxgi::test
