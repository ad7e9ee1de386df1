// Scene-scale invariance: the same scene translated by 10^4 units, or scaled by
// 10^-3 or 10^3, with its camera and lights, renders the same image. "Lights with
// it": punctual lights move with the scene and point intensities scale by s^2
// (writeTransformedGltf); emissive surfaces are radiance and need nothing.
//
// What makes it hold: the loader composes transforms in double and stores
// positions relative to the bounds' centre (Scene::origin), and the path tracer's
// ray offsets are relative to the scene's size.
//
// Tolerance: every variant renders with the same seed, so its image differs from
// the original's only where float rounding sends a path elsewhere. The yardstick is
// the difference between two seeds of the original (independent noise at this spp):
// a variant must differ by less than a fifth of that, and its mean by under 0.5 %.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gl/program_cache.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/scene_builder.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

std::vector<float> render(const std::string& path, render::Mode mode, uint32_t seed,
                          bool voxelRays) {
  const scene::Scene s = scene::loadGltf(path);
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::RenderSettings rs;
  rs.width = rs.height = 64;
  rs.mode = mode;
  rs.spp = 16;
  rs.pathtrace.seed = seed;
  rs.rtgi.seed = seed;
  rs.rtgi.exactRays = !voxelRays;
  // With the voxels' rays, the G-buffer rasterized too: no ray in world units.
  if (voxelRays) rs.rtgi.primary = render::RtgiPass::Settings::Primary::kRaster;
  // Nor photons: the caustics stage traces them in world units, each landing in one
  // pixel, and a rounding that moves one to the next pixel moves all of its light
  // (at 1e3 times the size: a relative RMSE of 0.003). The rtgi variant keeps them,
  // within its seed-to-seed noise.
  if (voxelRays) rs.rtgi.caustics = false;
  rs.octree.seed = seed;
  rs.voxels = 64;
  render::Renderer r(programs, s, rs);
  // rtgi: a few frames of accumulation, the same random numbers in every variant.
  for (int f = 0; f < (mode == render::Mode::kRtgi ? 4 : 1); ++f) r.renderFrame();
  return r.readLinear();
}

double mean(const std::vector<float>& px) {
  double sum = 0.0;
  for (size_t i = 0; i < px.size(); i += 4) sum += px[i] + px[i + 1] + px[i + 2];
  return sum / static_cast<double>(px.size() / 4 * 3);
}

// RMSE over RGB, relative to b's mean.
double relRmse(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); i += 4)
    for (size_t c = 0; c < 3; ++c) sum += (a[i + c] - b[i + c]) * (a[i + c] - b[i + c]);
  return std::sqrt(sum / static_cast<double>(a.size() / 4 * 3)) / mean(b);
}

bool allFinite(const std::vector<float>& px) {
  for (float v : px)
    if (!std::isfinite(v)) return false;
  return true;
}

struct Variant {
  const char* name;
  glm::dvec3 translation;
  double scale;
};
const Variant kVariants[] = {{"translated 1e4", glm::dvec3(1e4, -1e4, 1e4), 1.0},
                             {"scaled 1e-3", glm::dvec3(0.0), 1e-3},
                             {"scaled 1e3", glm::dvec3(0.0), 1e3}};

// `voxelRays`: rtgi's rays march the voxels only and its G-buffer is rasterized
// (every ray in voxel units: the image is the same to float rounding, bound 1e-3). Otherwise rtgi's
// rays hit the triangles in world units, and rounding may send a ray elsewhere, as in the path
// tracer.
void expectScaleInvariant(const std::string& source, render::Mode mode, bool voxelRays = false) {
  const std::vector<float> original = render(source, mode, 1, voxelRays);
  ASSERT_TRUE(allFinite(original));
  ASSERT_GT(mean(original), 0.0);
  const bool noisy =
      mode == render::Mode::kPathtrace || (mode == render::Mode::kRtgi && !voxelRays);
  const double noise = noisy ? relRmse(render(source, mode, 2, voxelRays), original) : 0.0;
  for (const Variant& v : kVariants) {
    SCOPED_TRACE(v.name);
    const std::string path = writeTransformedGltf(source, v.translation, v.scale);
    // The copy really is moved and scaled.
    const scene::Scene a = scene::loadGltf(source), b = scene::loadGltf(path);
    EXPECT_NEAR(b.bounds.diagonal() / a.bounds.diagonal(), v.scale, 1e-4 * v.scale);
    const glm::dvec3 shift = b.origin - (a.origin * v.scale + v.translation);
    EXPECT_LT(glm::length(shift), 1e-6 * (glm::length(v.translation) + v.scale));
    const std::vector<float> moved = render(path, mode, 1, voxelRays);
    ASSERT_TRUE(allFinite(moved));
    const double diff = relRmse(moved, original);
    const double meanRatio = mean(moved) / mean(original);
    std::printf("%s, %s: relative RMSE %.5f (seed-to-seed noise %.5f), mean ratio %.5f\n",
                render::modeName(mode), v.name, diff, noise, meanRatio);
    EXPECT_LT(diff, noisy ? 0.2 * noise : 1e-3);
    EXPECT_NEAR(meanRatio, 1.0, 5e-3);
  }
}

class ScaleInvarianceTest : public GlTest {};

TEST_F(ScaleInvarianceTest, CornellRoomPathtrace) {
  expectScaleInvariant(cornellRoom(), render::Mode::kPathtrace);
}

// rtgi: the grid is fitted to the scene, and the rays hit the triangles with offsets
// relative to the voxel size, so the image is the same at any position and scale up
// to where rounding sends a ray elsewhere.
TEST_F(ScaleInvarianceTest, CornellRoomRtgi) {
  expectScaleInvariant(cornellRoom(), render::Mode::kRtgi);
}

// With --voxel-rays every ray is marched in voxel units: the voxels, the rays and the
// image are the same to float rounding.
TEST_F(ScaleInvarianceTest, CornellRoomRtgiVoxelRays) {
  expectScaleInvariant(cornellRoom(), render::Mode::kRtgi, true);
}

TEST_F(ScaleInvarianceTest, CornellRoomRaster) {
  expectScaleInvariant(cornellRoom(), render::Mode::kRaster);
}

// A quad under a point light: its intensity must scale by s^2.
TEST_F(ScaleInvarianceTest, PointLitQuad) {
  const std::string quad = writeMeshGltf(
      "lit_quad.gltf", {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {0, 1, 2, 0, 2, 3});
  expectScaleInvariant(quad, render::Mode::kPathtrace);
  expectScaleInvariant(quad, render::Mode::kRaster);
}

}  // namespace
}  // namespace voxgi::test
