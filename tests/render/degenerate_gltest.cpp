// Degenerate geometry: zero-area and collinear triangles, duplicate vertices and
// indices, missing, zero and NaN normals. The loader drops or repairs them with
// one summarised warning per kind, and no pixel of a raster or path-traced image
// is NaN or Inf, whether the degenerate triangles came through the loader or were
// handed to the renderer directly.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/log.h"
#include "gl/program_cache.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/scene_builder.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

// A unit quad at z = 0 (triangles 0 and 1) and, after it, five degenerate triangles.
const std::vector<glm::vec3> kPositions = {
    {-1, -1, 0},   {1, -1, 0},       {1, 1, 0},     {-1, 1, 0},  // the quad
    {0.2, 0.2, 0}, {0.2, 0.2, 0},    {0.2, 0.2, 0},              // three equal corners
    {0, 0, 0},     {0.5, 0.5, 0},    {1, 1, 0},                  // exactly collinear
    {-1, 0, 0.1f}, {0, 1e-7f, 0.1f}, {1, 0, 0.1f},               // collinear up to 1e-7
};
const std::vector<uint32_t> kIndices = {0, 1, 2, 0,  2,  3,  // kept
                                        4, 5, 6,             // duplicate vertices
                                        2, 2, 3,             // duplicate index
                                        7, 8, 9, 10, 11, 12};
constexpr size_t kDegenerate = 4;  // the last only in float (nonzero in double)

std::vector<glm::vec3> normals() {
  std::vector<glm::vec3> n(kPositions.size(), glm::vec3(0, 0, 1));
  n[0] = glm::vec3(kNaN, 0, 1);  // NaN
  n[1] = glm::vec3(0.0f);        // zero
  return n;
}

size_t countContaining(const std::vector<std::string>& lines, const std::string& part) {
  size_t n = 0;
  for (const std::string& l : lines) n += l.find(part) != std::string::npos;
  return n;
}

void expectUnitNormalsAlongZ(const scene::Scene& s) {
  for (uint32_t i : s.indices) {
    const glm::vec3 n = s.vertices[i].normal;
    ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)) << i;
    EXPECT_NEAR(std::abs(n.z), 1.0f, 1e-5f) << "vertex " << i;
  }
}

TEST(DegenerateGeometry, LoaderDropsAndRepairsWithOneWarningEach) {
  const scene::Scene s =
      scene::loadGltf(writeMeshGltf("degenerate.gltf", kPositions, kIndices, normals()));
  EXPECT_EQ(s.triangleCount(), 2u);
  EXPECT_EQ(countContaining(s.warnings, "dropped "), 1u);
  EXPECT_EQ(
      countContaining(s.warnings, voxgi::strf("dropped %zu degenerate triangles", kDegenerate)),
      1u);
  EXPECT_EQ(countContaining(s.warnings, "repaired 2 zero or NaN normals"), 1u);
  EXPECT_EQ(s.warnings.size(), 2u);
  expectUnitNormalsAlongZ(s);
}

TEST(DegenerateGeometry, MissingNormalsGeneratedWithoutWarning) {
  const scene::Scene s = scene::loadGltf(writeMeshGltf("no_normals.gltf", kPositions, kIndices));
  EXPECT_EQ(s.triangleCount(), 2u);
  EXPECT_EQ(countContaining(s.warnings, "repaired"), 0u);
  EXPECT_EQ(countContaining(s.warnings, "dropped "), 1u);
  expectUnitNormalsAlongZ(s);
}

std::vector<float> render(const scene::Scene& s, render::Mode mode) {
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::RenderSettings rs;
  rs.width = rs.height = 64;
  rs.mode = mode;
  rs.spp = 4;
  render::Renderer r(programs, s, rs);
  r.renderFrame();
  // Nor a NaN or Inf that accumulation or the octree replaced on the way.
  EXPECT_EQ(r.nonfiniteTerms(), 0u);
  return r.readLinear();
}

size_t nonFinite(const std::vector<float>& px) {
  size_t n = 0;
  for (float v : px) n += !std::isfinite(v);
  return n;
}

double meanRgb(const std::vector<float>& px) {
  double sum = 0.0;
  for (size_t i = 0; i < px.size(); i += 4) sum += px[i] + px[i + 1] + px[i + 2];
  return sum / static_cast<double>(px.size() / 4 * 3);
}

class DegenerateRenderTest : public GlTest {};

TEST_F(DegenerateRenderTest, LoadedSceneHasNoNanPixel) {
  for (bool withNormals : {true, false}) {
    const scene::Scene s =
        scene::loadGltf(writeMeshGltf("degenerate_render.gltf", kPositions, kIndices,
                                      withNormals ? normals() : std::vector<glm::vec3>{}));
    for (render::Mode mode :
         {render::Mode::kRaster, render::Mode::kRtgi, render::Mode::kPathtrace}) {
      SCOPED_TRACE(std::string(render::modeName(mode)) + (withNormals ? "" : ", no normals"));
      const std::vector<float> px = render(s, mode);
      EXPECT_EQ(nonFinite(px), 0u);
      EXPECT_GT(meanRgb(px), 0.0);  // the lit quad is seen
    }
  }
}

// The renderer's own guard, without the loader: the same triangles (normals valid,
// since the renderer is promised those) handed over as they are, some emissive so
// that the path tracer's light sampling meets zero-area emitters too.
TEST_F(DegenerateRenderTest, UnfilteredTrianglesGiveNoNanPixel) {
  SceneBuilder b;
  const int grey = b.addMaterial(glm::vec3(0.7f));
  const int lamp = b.addMaterial(glm::vec3(0.5f), glm::vec3(4.0f));
  scene::Scene& s = b.scene();
  for (const glm::vec3& p : kPositions) s.vertices.push_back({p, glm::vec3(0, 0, 1), glm::vec2(0)});
  s.indices = kIndices;
  s.draws.push_back({0, 6, grey, -1, -1});
  s.draws.push_back({6, static_cast<uint32_t>(kIndices.size() - 6), lamp, -1, -1});
  scene::Light light;
  light.position = glm::vec3(0, 0, 2);
  light.intensity = 10.0f;
  s.lights.push_back(light);
  scene::Scene scene = b.finish();
  scene.camera.position = glm::vec3(0, 0, 3);
  scene.camera.forward = glm::vec3(0, 0, -1);
  scene.camera.fromFile = true;
  for (render::Mode mode : {render::Mode::kRaster, render::Mode::kRtgi, render::Mode::kPathtrace}) {
    SCOPED_TRACE(render::modeName(mode));
    const std::vector<float> px = render(scene, mode);
    EXPECT_EQ(nonFinite(px), 0u);
    EXPECT_GT(meanRgb(px), 0.0);
  }
}

}  // namespace
}  // namespace voxgi::test
