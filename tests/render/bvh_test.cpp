// The BVH against brute force: random rays through random triangle soups and the
// Cornell room give the same closest hit and the same occlusion answer.
#include <gtest/gtest.h>

#include <bit>
#include <cstdio>
#include <random>

#include "render/bvh.h"
#include "scene/gltf_loader.h"
#include "support/test_paths.h"

namespace voxgi::render {
namespace {

bool bruteForce(const std::vector<BvhTriangle>& tris, const BvhRay& ray, BvhHit* hit) {
  bool found = false;
  BvhRay r = ray;
  for (size_t i = 0; i < tris.size(); ++i) {
    float t, u, v;
    if (intersectTriangle(r, tris[i].v0, tris[i].v1 - tris[i].v0, tris[i].v2 - tris[i].v0, &t, &u,
                          &v)) {
      found = true;
      r.tMax = t;
      *hit = {t, u, v, static_cast<int>(i)};
    }
  }
  return found;
}

std::vector<BvhTriangle> randomSoup(std::mt19937& rng, int count, float size) {
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f), off(-size, size);
  std::vector<BvhTriangle> tris;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 c(pos(rng), pos(rng), pos(rng));
    tris.push_back({c + glm::vec3(off(rng), off(rng), off(rng)),
                    c + glm::vec3(off(rng), off(rng), off(rng)),
                    c + glm::vec3(off(rng), off(rng), off(rng))});
  }
  return tris;
}

void checkRandomRays(const std::vector<BvhTriangle>& tris, const Bvh& bvh, std::mt19937& rng,
                     int rays, float extent) {
  std::uniform_real_distribution<float> pos(-extent, extent);
  std::normal_distribution<float> dir;
  int hits = 0;
  for (int i = 0; i < rays; ++i) {
    BvhRay ray;
    ray.origin = glm::vec3(pos(rng), pos(rng), pos(rng));
    ray.direction = glm::normalize(glm::vec3(dir(rng), dir(rng), dir(rng)));
    if (i % 7 == 0) ray.direction = glm::vec3(0.0f, i % 2 ? 1.0f : -1.0f, 0.0f);  // axis-parallel
    if (i % 5 == 0) ray.tMax = 0.5f;
    BvhHit a, b;
    const bool ha = bvh.intersect(ray, &a);
    const bool hb = bruteForce(tris, ray, &b);
    ASSERT_EQ(ha, hb) << "ray " << i;
    ASSERT_EQ(bvh.occluded(ray), hb) << "ray " << i;
    if (!ha) continue;
    ++hits;
    ASSERT_FLOAT_EQ(a.t, b.t) << "ray " << i;
    // Equal t on two triangles (a shared edge) may pick either.
    if (a.triangle != b.triangle) continue;
    EXPECT_FLOAT_EQ(a.u, b.u);
    EXPECT_FLOAT_EQ(a.v, b.v);
  }
  if (tris.size() >= 1000) {
    EXPECT_GT(hits, rays / 10);
  }
}

TEST(Bvh, MatchesBruteForceOnRandomSoups) {
  std::mt19937 rng(7);
  for (int count : {1, 2, 3, 9, 100, 2000}) {
    const auto tris = randomSoup(rng, count, 0.2f);
    const Bvh bvh(tris);
    ASSERT_EQ(bvh.triangleCount(), tris.size());
    checkRandomRays(tris, bvh, rng, 3000, 1.5f);
  }
}

TEST(Bvh, EmptyAndDegenerateInputs) {
  const Bvh empty(std::vector<BvhTriangle>{});
  BvhHit hit;
  EXPECT_FALSE(empty.intersect({glm::vec3(0.0f), glm::vec3(0, 0, 1)}, &hit));
  EXPECT_FALSE(empty.occluded({glm::vec3(0.0f), glm::vec3(0, 0, 1)}));
  // Many triangles with the same centroid: no SAH split exists, size still bounds leaves.
  std::vector<BvhTriangle> same(100,
                                {glm::vec3(-1, -1, 0), glm::vec3(1, -1, 0), glm::vec3(0, 1, 0)});
  const Bvh bvh(same);
  for (const gpu::GpuBvhNode& n : bvh.nodes()) {
    EXPECT_LE(std::bit_cast<uint32_t>(n.leftMax.w), gpu::kPtMaxLeafSize);
    EXPECT_LE(std::bit_cast<uint32_t>(n.rightMax.w), gpu::kPtMaxLeafSize);
  }
  ASSERT_TRUE(bvh.intersect({glm::vec3(0, 0, 5), glm::vec3(0, 0, -1)}, &hit));
  EXPECT_FLOAT_EQ(hit.t, 5.0f);
}

TEST(Bvh, CornellRoomMatchesBruteForce) {
  const scene::Scene s = scene::loadGltf(test::cornellRoom());
  std::vector<BvhTriangle> tris;
  for (size_t i = 0; i < s.indices.size(); i += 3)
    tris.push_back({s.vertices[s.indices[i]].position, s.vertices[s.indices[i + 1]].position,
                    s.vertices[s.indices[i + 2]].position});
  const Bvh bvh(tris);
  std::printf("cornell_room: %zu triangles, %zu nodes, depth %d, SAH cost %.1f\n", tris.size(),
              bvh.nodes().size(), bvh.depth(), bvh.sahCost());
  EXPECT_LT(bvh.sahCost(), 60.0);  // a bad split heuristic is far above this
  std::mt19937 rng(11);
  // Rays from inside the room.
  std::uniform_real_distribution<float> px(-0.99f, 0.99f), py(0.01f, 1.98f);
  std::normal_distribution<float> dir;
  for (int i = 0; i < 300; ++i) {
    BvhRay ray{glm::vec3(px(rng), py(rng), px(rng)),
               glm::normalize(glm::vec3(dir(rng), dir(rng), dir(rng)))};
    BvhHit a, b;
    const bool ha = bvh.intersect(ray, &a);
    ASSERT_EQ(ha, bruteForce(tris, ray, &b));
    if (ha) {
      EXPECT_FLOAT_EQ(a.t, b.t);
    }
  }
}

}  // namespace
}  // namespace voxgi::render
