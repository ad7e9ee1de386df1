// Vertex colours (COLOR_0) in every mode that shows base colour: the quad of
// tests/data/vertex_colors (make_vertex_colors.py), white, with red vertex colours on
// its left half and green on its right, shows red on the left and green on the right
// in raster, rtgi and the path tracer on both devices, which agree, and colours the
// voxels (both voxelization paths); `--effects -colors` turns them off.
#include <gtest/gtest.h>

#include <cstdio>

#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/mode_runs.h"
#include "support/test_paths.h"
#include "voxel/voxelize_pass.h"

namespace voxgi::test {
namespace {

constexpr int kSize = 32;

scene::Scene redGreenQuad() {
  return scene::loadGltf(testDataDir() + "/vertex_colors/red_green_quad.gltf");
}

render::RenderSettings settingsFor(render::Mode mode) {
  render::RenderSettings rs;
  rs.mode = mode;
  rs.width = rs.height = kSize;
  rs.voxels = 64;
  rs.spp = 32;
  return rs;
}

std::vector<float> renderImage(const scene::Scene& s, const render::RenderSettings& rs,
                               int frames = 1) {
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::Renderer r(programs, s, rs);
  EXPECT_EQ(r.effects().has(scene::Effect::kColors), rs.effects.empty()) << r.effects().summary();
  for (int f = 0; f < frames; ++f) r.renderFrame();
  return r.readLinear();
}

// Mean RGB of the image's left (x < size / 2) or right half.
glm::dvec3 halfMean(const std::vector<float>& px, bool left) {
  glm::dvec3 sum(0.0);
  for (int y = 0; y < kSize; ++y)
    for (int x = left ? 0 : kSize / 2; x < (left ? kSize / 2 : kSize); ++x) {
      const size_t i = (static_cast<size_t>(y) * kSize + static_cast<size_t>(x)) * 4;
      sum += glm::dvec3(px[i], px[i + 1], px[i + 2]);
    }
  return sum / static_cast<double>(kSize * kSize / 2);
}

class VertexColorsTest : public GlTest {};

TEST_F(VertexColorsTest, EveryModeShowsThem) {
  const scene::Scene s = redGreenQuad();
  ASSERT_TRUE(s.hasVertexColors());
  glm::dvec3 pathtraced[2][2];  // [device][left, right]
  for (const ModeRun& run : kEveryMode) {
    const auto px = renderRun(s, run, settingsFor(run.mode), scene::Effect::kColors);
    const glm::dvec3 left = halfMean(px, true), right = halfMean(px, false);
    std::printf("%s: left half (%.4f %.4f %.4f), right half (%.4f %.4f %.4f)\n", run.name, left.r,
                left.g, left.b, right.r, right.g, right.b);
    EXPECT_GT(left.r, 0.05) << run.name;
    EXPECT_LT(left.g, 0.02 * left.r) << run.name;
    EXPECT_LT(left.b, 0.02 * left.r) << run.name;
    EXPECT_GT(right.g, 0.05) << run.name;
    EXPECT_LT(right.r, 0.02 * right.g) << run.name;
    EXPECT_LT(right.b, 0.02 * right.g) << run.name;
    if (run.mode == render::Mode::kPathtrace) {
      const int d = run.device == render::PathtraceDevice::kGl ? 0 : 1;
      pathtraced[d][0] = left;
      pathtraced[d][1] = right;
    }
  }
  // The devices agree (32 spp of a directly lit quad: within 3%).
  EXPECT_NEAR(pathtraced[0][0].r, pathtraced[1][0].r, 0.03 * pathtraced[1][0].r);
  EXPECT_NEAR(pathtraced[0][1].g, pathtraced[1][1].g, 0.03 * pathtraced[1][1].g);
}

TEST_F(VertexColorsTest, EffectsOffShowsTheMaterialAlone) {
  const scene::Scene s = redGreenQuad();
  for (render::Mode mode : {render::Mode::kRaster, render::Mode::kPathtrace}) {
    render::RenderSettings rs = settingsFor(mode);
    rs.effects = "-colors";
    const auto px = renderImage(s, rs);
    const glm::dvec3 left = halfMean(px, true), right = halfMean(px, false);
    std::printf("mode %d, -colors: left (%.4f %.4f %.4f), right (%.4f %.4f %.4f)\n",
                static_cast<int>(mode), left.r, left.g, left.b, right.r, right.g, right.b);
    // White: every channel alike.
    EXPECT_NEAR(left.g, left.r, 0.05 * left.r + 1e-3);
    EXPECT_NEAR(right.r, right.g, 0.05 * right.g + 1e-3);
  }
}

// The voxels' albedo: red left of the middle, green right of it, whether the
// triangles are rasterized or taken by the compute path for small triangles.
TEST_F(VertexColorsTest, VoxelAlbedo) {
  scene::Scene s = redGreenQuad();
  // A grid four times the fitted one: the quad's triangles span a few voxels, small
  // enough for the compute path.
  const glm::vec3 centre = s.scale.gridOrigin + 0.5f * s.scale.gridSize;
  s.scale.gridSize *= 4.0f;
  s.scale.gridOrigin = centre - 0.5f * s.scale.gridSize;
  for (bool smallInCompute : {false, true}) {
    constexpr int n = 32;
    gl::ProgramCache programs(sourceDir() + "/shaders");
    gl::StageTimer timer;
    scene::GpuScene gs(s);
    gl::FrameContext ctx{programs, timer, n, n, 0};
    voxel::VoxelizePass::Settings settings;
    settings.resolution = n;
    settings.inspectSums = true;  // counts the triangles the compute path takes
    settings.smallTrianglesInCompute = smallInCompute;
    voxel::VoxelizePass pass(programs, "llvmpipe", settings);
    pass.execute(ctx, gs);
    timer.resolve();
    if (smallInCompute) {
      EXPECT_GT(pass.stats().smallTriangles, 0u);
    }
    const std::vector<uint8_t> albedo = pass.readAlbedo();
    glm::dvec3 left(0.0), right(0.0);
    const glm::vec3 origin = s.scale.gridOrigin;
    const float voxelSize = s.scale.gridSize / static_cast<float>(n);
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const size_t i = (static_cast<size_t>(z) * n * n + static_cast<size_t>(y) * n +
                            static_cast<size_t>(x)) *
                           4;
          if (albedo[i + 3] == 0) continue;
          const float cx = origin.x + (static_cast<float>(x) + 0.5f) * voxelSize;
          const glm::dvec3 c(albedo[i], albedo[i + 1], albedo[i + 2]);
          if (cx < -voxelSize) left += c;
          if (cx > voxelSize) right += c;
        }
    std::printf("voxels (%s): left (%.0f %.0f %.0f), right (%.0f %.0f %.0f)\n",
                smallInCompute ? "compute" : "raster", left.r, left.g, left.b, right.r, right.g,
                right.b);
    EXPECT_GT(left.r, 0.0);
    EXPECT_LT(left.g, 0.02 * left.r);
    EXPECT_GT(right.g, 0.0);
    EXPECT_LT(right.r, 0.02 * right.g);
  }
}

}  // namespace
}  // namespace voxgi::test
