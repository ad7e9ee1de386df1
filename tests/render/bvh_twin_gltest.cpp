// The BVH traversal (bvh_shared.h) agrees between its GLSL build (run by llvmpipe),
// which the path tracer and rtgi's rays run, and its C++ build, which render::Bvh
// runs and tests/render/bvh_test.cpp checks against brute force: the same hit
// (triangle, distance, barycentrics) or the same miss, closest and any hit, on random
// rays through random triangle soups and the Cornell room.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "bvh_shared.h"
#include "render/bvh.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"
#include "support/twin_shader.h"

namespace voxgi::test {
namespace {

// Share of rays on which both builds agree; rays alternate closest and any hit.
double agreement(const render::Bvh& bvh, std::mt19937& rng, float extent, int* hits) {
  constexpr int kRays = 4096;
  std::uniform_real_distribution<float> pos(-extent, extent);
  std::normal_distribution<float> dir;
  std::vector<glm::vec4> rays;
  for (int i = 0; i < kRays; ++i) {
    glm::vec3 d = glm::normalize(glm::vec3(dir(rng), dir(rng), dir(rng)));
    if (i % 7 == 0) d = glm::vec3(0.0f, i % 2 ? 1.0f : -1.0f, 0.0f);  // axis-parallel
    const float tMax = i % 5 == 0 ? 0.5f : 1e30f;
    rays.push_back(glm::vec4(pos(rng), pos(rng), pos(rng), tMax));
    rays.push_back(glm::vec4(d, i % 2 == 0 ? 0.0f : 1.0f));
  }
  const auto& tris = bvh.gpuTriangles();
  const std::vector<glm::vec4> gpuOut = runTwinShader<glm::vec4>(
      "bvh_twin.comp", {twinInput(rays), twinInput(bvh.nodes()), twinInput(tris)}, kRays);

  const gpu::BvhArrays arrays{bvh.nodes().data(), tris.data()};
  int same = 0;
  *hits = 0;
  for (int i = 0; i < kRays; ++i) {
    const glm::vec4 a = rays[2 * static_cast<size_t>(i)], b = rays[2 * static_cast<size_t>(i) + 1];
    float t = 0.0f;
    uint32_t tri = 0;
    glm::vec2 bc(0.0f);
    const bool hit =
        gpu::bvhTrace(arrays, glm::vec3(a), glm::vec3(b), 0.0f, a.w, b.w > 0.5f, t, tri, bc);
    const glm::vec4 g = gpuOut[static_cast<size_t>(i)];
    if (hit) ++*hits;
    auto close = [](float x, float y) {
      return std::abs(x - y) <= 1e-4f * std::max(std::abs(x), std::abs(y)) + 1e-5f;
    };
    if (g.x == (hit ? static_cast<float>(tri) : -1.0f) && close(g.y, t) && close(g.z, bc.x) &&
        close(g.w, bc.y))
      ++same;
  }
  return static_cast<double>(same) / kRays;
}

TEST_F(GlTest, BvhTraversalAgreesBetweenGlslAndCpp) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f), off(-0.2f, 0.2f);
  std::vector<render::BvhTriangle> soup;
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 c(pos(rng), pos(rng), pos(rng));
    soup.push_back({c + glm::vec3(off(rng), off(rng), off(rng)),
                    c + glm::vec3(off(rng), off(rng), off(rng)),
                    c + glm::vec3(off(rng), off(rng), off(rng))});
  }
  int hits = 0;
  const double soupShare = agreement(render::Bvh(soup), rng, 1.5f, &hits);
  std::printf("soup: %.2f%% of rays agree, %d hits\n", 100.0 * soupShare, hits);
  EXPECT_GT(hits, 4096 / 10);
  // Rounding can move a hit across a shared edge on a handful of rays; a formula
  // read differently fails most of them.
  EXPECT_GE(soupShare, 0.995);

  const scene::Scene s = scene::loadGltf(cornellRoom());
  std::vector<render::BvhTriangle> room;
  for (size_t i = 0; i < s.indices.size(); i += 3)
    room.push_back({s.vertices[s.indices[i]].position, s.vertices[s.indices[i + 1]].position,
                    s.vertices[s.indices[i + 2]].position});
  const double roomShare = agreement(render::Bvh(room), rng, 0.99f, &hits);
  std::printf("cornell_room: %.2f%% of rays agree, %d hits\n", 100.0 * roomShare, hits);
  EXPECT_GT(hits, 4096 / 2);
  EXPECT_GE(roomShare, 0.995);
}

}  // namespace
}  // namespace voxgi::test
