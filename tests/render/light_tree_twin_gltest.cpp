// The light tree's walk (light_tree_shared.h) agrees between its GLSL build (run by
// llvmpipe) and its C++ build, which tests/scene/light_tree_test.cpp checks against
// the emitters' exact contributions: the same emitter drawn, with the same
// probability, on random points, normals and numbers, walking down to nodes of at most
// kLightTreeLeafDraw emitters (the pixels) or 8 (as rtgi's indirect hits may).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>
#include <vector>

#include "scene/light_tree.h"
#include "support/gl_fixture.h"
#include "support/twin_shader.h"

namespace voxgi::test {
namespace {

glm::vec3 unitVector(std::mt19937& rng) {
  std::normal_distribution<float> g;
  return glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
}

TEST_F(GlTest, LightTreeWalkAgreesBetweenGlslAndCpp) {
  // 400 emitters: clusters over a sphere and triangles around it, one- and
  // two-sided, so that the walk takes binary steps before it draws among leaves.
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::vector<scene::Emitter> emitters;
  for (int i = 0; i < 400; ++i) {
    scene::Emitter e;
    const glm::vec3 n = unitVector(rng);
    e.radiance = glm::vec3(1.0f + 4.0f * u01(rng));
    if (i % 2 == 0) {
      e.kind = scene::Emitter::Kind::kCluster;
      e.normal = n;
      e.v0 = glm::vec3(0.0f, 2.0f, 0.0f) + 0.3f * n;
      e.area = 0.002f;
    } else {
      e.v0 = glm::vec3(0.0f, 2.0f, 0.0f) + 1.5f * n;
      e.v1 = e.v0 + 0.1f * unitVector(rng);
      e.v2 = e.v0 + 0.1f * unitVector(rng);
      e.twoSided = i % 3 == 0;
    }
    emitters.push_back(e);
  }
  const auto tree = scene::buildLightTree(scene::packEmitters(emitters));
  constexpr int kCases = 4096;
  std::vector<glm::vec4> inputs;
  for (int i = 0; i < kCases; ++i) {
    const glm::vec3 p(4.0f * u01(rng) - 2.0f, 4.0f * u01(rng), 4.0f * u01(rng) - 2.0f);
    inputs.push_back(glm::vec4(p, u01(rng)));
    inputs.push_back(glm::vec4(unitVector(rng), u01(rng)));
  }

  const std::vector<glm::vec4> gpuOut = runTwinShader<glm::vec4>(
      "light_tree_twin.comp", {twinInput(inputs), twinInput(tree)}, kCases);

  // Every case agrees (the same emitter, its pmf within 1e-4 relative), or lies on a
  // boundary: rounding can move a walk across the boundary between two children
  // when the random number falls within a rounding error of it. Such a case is
  // accepted only if the C++ walk, with the number moved by 1e-5 either way, picks
  // what the GLSL one picked; a formula read differently fails that.
  auto agrees = [](const glm::vec4& g, int pick, float pmf) {
    return static_cast<int>(g.x) == pick && std::abs(g.y - pmf) <= 1e-4f * pmf + 1e-9f;
  };
  int same = 0, boundary = 0, differ = 0, drawn = 0;
  for (int i = 0; i < kCases; ++i) {
    const glm::vec3 p(inputs[2 * i]), n(inputs[2 * i + 1]);
    const uint32_t stream = std::bit_cast<uint32_t>(inputs[2 * i + 1].w);
    const float leafDraw = i % 2 != 0 ? 8.0f : gpu::kLightTreeLeafDraw;
    float pmf = 0.0f;
    const int pick = gpu::pickLightTree(tree.data(), inputs[2 * i].w, stream, p, n, leafDraw, pmf);
    const glm::vec4 g = gpuOut[static_cast<size_t>(i)];
    if (pick >= 0) ++drawn;
    if (agrees(g, pick, pmf)) {
      ++same;
      continue;
    }
    bool nearby = false;
    for (float du : {-1e-5f, 1e-5f}) {
      float nearPmf = 0.0f;
      const int nearPick =
          gpu::pickLightTree(tree.data(), inputs[2 * i].w + du, stream, p, n, leafDraw, nearPmf);
      nearby = nearby || agrees(g, nearPick, nearPmf);
    }
    ++(nearby ? boundary : differ);
  }
  std::printf("%d cases: %d agree, %d on a boundary, %d differ (%d drew an emitter)\n", kCases,
              same, boundary, differ, drawn);
  EXPECT_GT(drawn, kCases / 2);  // most cases reach an emitter
  EXPECT_EQ(differ, 0);
}

}  // namespace
}  // namespace voxgi::test
