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

struct Agreement {
  int same = 0;    // the same hit (triangle, distance, barycentrics) or the same miss
  int twin = 0;    // closest hits at the same distance on another triangle, any hits on
                   // different triangles: both answers are right
  int edge = 0;    // one hit, one miss, the hit within 1e-4 of its triangle's edge
  int differ = 0;  // anything else: a formula read differently
  int hits = 0;
};

// Compares the two builds on random rays (alternately closest and any hit). Where
// they differ, the difference must be one that float rounding alone can make: a
// ray through a shared edge or a coplanar overlap finds another triangle at the same
// distance, and a ray grazing an edge may hit in one build and miss in the other.
Agreement agreement(const render::Bvh& bvh, std::mt19937& rng, float extent) {
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
  auto close = [](float x, float y) {
    return std::abs(x - y) <= 1e-4f * std::max(std::abs(x), std::abs(y)) + 1e-5f;
  };
  auto onEdge = [](glm::vec2 b) { return std::min({b.x, b.y, 1.0f - b.x - b.y}) < 1e-4f; };
  Agreement r;
  for (int i = 0; i < kRays; ++i) {
    const glm::vec4 a = rays[2 * static_cast<size_t>(i)], b = rays[2 * static_cast<size_t>(i) + 1];
    const bool anyHit = b.w > 0.5f;
    float t = 0.0f;
    uint32_t tri = 0;
    glm::vec2 bc(0.0f);
    const bool hit =
        gpu::bvhTrace(arrays, glm::vec3(a), glm::vec3(b), 0.0f, a.w, anyHit, t, tri, bc);
    const glm::vec4 g = gpuOut[static_cast<size_t>(i)];
    const bool gHit = g.x >= 0.0f;
    if (hit) ++r.hits;
    if (hit == gHit && (!hit || (g.x == static_cast<float>(tri) && close(g.y, t) &&
                                 close(g.z, bc.x) && close(g.w, bc.y))))
      ++r.same;
    else if (hit && gHit && g.x != static_cast<float>(tri) && (anyHit || close(g.y, t)))
      ++r.twin;
    else if (hit != gHit && onEdge(hit ? bc : glm::vec2(g.z, g.w)))
      ++r.edge;
    else
      ++r.differ;
  }
  std::printf(
      "%d rays: %d the same, %d another triangle at the same distance, %d grazing an "
      "edge, %d differ (%d hits)\n",
      kRays, r.same, r.twin, r.edge, r.differ, r.hits);
  return r;
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
  const Agreement soupRays = agreement(render::Bvh(soup), rng, 1.5f);
  EXPECT_GT(soupRays.hits, 4096 / 10);
  EXPECT_EQ(soupRays.differ, 0);

  const scene::Scene s = scene::loadGltf(cornellRoom());
  std::vector<render::BvhTriangle> room;
  for (size_t i = 0; i < s.indices.size(); i += 3)
    room.push_back({s.vertices[s.indices[i]].position, s.vertices[s.indices[i + 1]].position,
                    s.vertices[s.indices[i + 2]].position});
  const Agreement roomRays = agreement(render::Bvh(room), rng, 0.99f);
  EXPECT_GT(roomRays.hits, 4096 / 2);
  EXPECT_EQ(roomRays.differ, 0);
}

}  // namespace
}  // namespace voxgi::test
