// The BVH against brute force: random rays through random triangle soups and the
// Cornell room give the same closest hit and the same occlusion answer.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <random>

#include <tbb/global_control.h>

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

// The builder's specification, written plainly: one thread, recursive, 16 bins per
// axis over the centroid bounds, the cheapest split by the surface area heuristic,
// the median below depth 24 or when no split exists, nodes in depth-first order
// (parent, left subtree, right subtree). The parallel builder must give the same
// nodes and the same triangle order, bit for bit, whatever the thread count.
struct ReferenceBuilder {
  struct Box {
    glm::vec3 lo{1e30f}, hi{-1e30f};
    void extend(const glm::vec3& p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
    void extend(const Box& b) { lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi); }
    float area() const {
      if (lo.x > hi.x) return 0.0f;
      const glm::vec3 d = hi - lo;
      return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
  };
  struct Child {
    Box box;
    uint32_t index = 0, count = 0;
  };
  std::vector<Box> boxes;
  std::vector<glm::vec3> centroids;
  std::vector<uint32_t> refs;
  std::vector<gpu::GpuBvhNode> nodes;

  uint32_t maxLeaf;

  explicit ReferenceBuilder(const std::vector<BvhTriangle>& tris,
                            uint32_t leafSize = gpu::kPtMaxLeafSize)
      : maxLeaf(leafSize) {
    for (const BvhTriangle& t : tris) {
      Box b;
      b.extend(t.v0), b.extend(t.v1), b.extend(t.v2);
      boxes.push_back(b);
      centroids.push_back(0.5f * (b.lo + b.hi));
    }
    refs.resize(tris.size());
    std::iota(refs.begin(), refs.end(), 0u);
    const Child root = build(0, static_cast<uint32_t>(tris.size()), 1);
    if (root.count > 0 || tris.empty()) nodes.insert(nodes.begin(), node(root, Child{}));
  }
  static gpu::GpuBvhNode node(const Child& l, const Child& r) {
    gpu::GpuBvhNode n{};
    n.leftMin = glm::vec4(l.box.lo, std::bit_cast<float>(l.index));
    n.leftMax = glm::vec4(l.box.hi, std::bit_cast<float>(l.count));
    n.rightMin = glm::vec4(r.box.lo, std::bit_cast<float>(r.index));
    n.rightMax = glm::vec4(r.box.hi, std::bit_cast<float>(r.count));
    return n;
  }
  uint32_t split(uint32_t begin, uint32_t end, const Box& box, int level) {
    const uint32_t count = end - begin;
    if (count <= 1) return end;
    Box cb;
    for (uint32_t i = begin; i < end; ++i) cb.extend(centroids[refs[i]]);
    const glm::vec3 extent = cb.hi - cb.lo;
    int axis = 0;
    if (extent.y > extent[axis]) axis = 1;
    if (extent.z > extent[axis]) axis = 2;
    auto median = [&] {
      const uint32_t mid = begin + count / 2;
      std::nth_element(
          refs.begin() + begin, refs.begin() + mid, refs.begin() + end,
          [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
      return mid;
    };
    if (!(extent[axis] > 0.0f)) return count > maxLeaf ? begin + count / 2 : end;
    if (level >= 24) return count > maxLeaf ? median() : end;
    const int nb = 16;
    float best = 1e30f;
    int bestAxis = -1, bestBin = -1;
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0f)) continue;
      std::vector<Box> bin(nb);
      std::vector<uint32_t> n(nb);
      for (uint32_t i = begin; i < end; ++i) {
        const int b = std::min(
            nb - 1, static_cast<int>((centroids[refs[i]][a] - cb.lo[a]) * (nb / extent[a])));
        bin[static_cast<size_t>(b)].extend(boxes[refs[i]]);
        ++n[static_cast<size_t>(b)];
      }
      for (int b = 1; b < nb; ++b) {
        Box l, r;
        uint32_t lc = 0, rc = 0;
        for (int k = 0; k < nb; ++k) {
          (k < b ? l : r).extend(bin[static_cast<size_t>(k)]);
          (k < b ? lc : rc) += n[static_cast<size_t>(k)];
        }
        if (lc == 0 || rc == 0) continue;
        const float cost = l.area() * static_cast<float>(lc) + r.area() * static_cast<float>(rc);
        if (cost < best) best = cost, bestAxis = a, bestBin = b;
      }
    }
    if (bestAxis < 0) return count > maxLeaf ? median() : end;
    if (count <= maxLeaf && static_cast<float>(count) <= 1.0f + best / std::max(box.area(), 1e-30f))
      return end;
    const float scale = nb / extent[bestAxis];
    auto mid = std::partition(refs.begin() + begin, refs.begin() + end, [&](uint32_t t) {
      return std::min(nb - 1, static_cast<int>((centroids[t][bestAxis] - cb.lo[bestAxis]) *
                                               scale)) < bestBin;
    });
    const auto m = static_cast<uint32_t>(mid - refs.begin());
    return m == begin || m == end ? median() : m;
  }
  Child build(uint32_t begin, uint32_t end, int level) {
    Child c;
    for (uint32_t i = begin; i < end; ++i) c.box.extend(boxes[refs[i]]);
    const uint32_t m = split(begin, end, c.box, level);
    if (m == end) {
      c.index = begin, c.count = end - begin;
      return c;
    }
    const auto at = static_cast<uint32_t>(nodes.size());
    nodes.emplace_back();
    const Child l = build(begin, m, level + 1);
    const Child r = build(m, end, level + 1);
    nodes[at] = node(l, r);
    c.index = at;
    return c;
  }
};

void expectSameTree(const Bvh& bvh, const ReferenceBuilder& ref, const char* what) {
  ASSERT_EQ(bvh.nodes().size(), ref.nodes.size()) << what;
  EXPECT_EQ(bvh.order(), ref.refs) << what;
  size_t differ = 0;
  for (size_t i = 0; i < ref.nodes.size(); ++i)
    differ += std::memcmp(&bvh.nodes()[i], &ref.nodes[i], sizeof(gpu::GpuBvhNode)) != 0;
  EXPECT_EQ(differ, 0u) << what << ": nodes that differ from the reference build";
}

// Soups large enough that the builder bins in parallel and hands subtrees to
// worker threads (ranges over 64k triangles), built with one thread and with all.
TEST(Bvh, ParallelBuildIsTheSerialBinnedSahBuild) {
  std::mt19937 rng(5);
  for (int count : {1, 2, 17, 5000, 200000}) {
    // Clustered: many triangles share bins, some ranges have centroids in one point.
    auto tris = randomSoup(rng, count, 0.01f);
    for (size_t i = 0; i + 1 < tris.size(); i += 97) tris[i + 1] = tris[i];
    const ReferenceBuilder ref(tris);
    {
      tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      expectSameTree(Bvh(tris), ref, "one thread");
    }
    expectSameTree(Bvh(tris), ref, "all threads");
  }
}

// Leaves of up to 4 triangles: the subtrees built by workers have fewer nodes than
// the room reserved for them, and the gaps are closed afterwards.
TEST(Bvh, ParallelBuildWithLargerLeavesIsTheSerialBuild) {
  std::mt19937 rng(9);
  // Each triangle three times: a range of copies can only be a leaf.
  std::vector<BvhTriangle> tris;
  for (const BvhTriangle& t : randomSoup(rng, 50000, 0.01f)) tris.insert(tris.end(), 3, t);
  const ReferenceBuilder ref(tris, 4);
  Bvh::Options options;
  options.maxLeafSize = 4;
  const Bvh bvh(tris, options);
  EXPECT_LT(bvh.nodes().size(), tris.size() / 2);  // N - 1 were reserved
  expectSameTree(bvh, ref, "leaves of 4");
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
