#include "render/bvh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>

#include "core/log.h"

namespace voxgi::render {
namespace {

constexpr int kMedianSplitDepth = 24;  // below this depth, split at the median: depth stays bounded

struct Box {
  glm::vec3 lo{1e30f}, hi{-1e30f};
  void extend(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void extend(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x; }
  float area() const {
    if (empty()) return 0.0f;
    const glm::vec3 d = hi - lo;
    return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
};

float bitsToFloat(uint32_t u) {
  return std::bit_cast<float>(u);
}

struct Builder {
  const std::vector<BvhTriangle>& tris;
  const Bvh::Options& options;
  std::vector<Box> boxes;
  std::vector<glm::vec3> centroids;
  std::vector<uint32_t> refs;
  std::vector<gpu::GpuBvhNode> nodes;
  int depth = 0;
  double sah = 0.0;  // un-normalised: sum of area x cost
  struct ChildRef {
    Box box;
    uint32_t index = 0, count = 0;
  };

  Box boundsOf(uint32_t begin, uint32_t end) const {
    Box b;
    for (uint32_t i = begin; i < end; ++i) b.extend(boxes[refs[i]]);
    return b;
  }

  // Returns the split position in [begin, end), or `end` for a leaf.
  uint32_t split(uint32_t begin, uint32_t end, const Box& box, int level) {
    const uint32_t count = end - begin;
    if (count <= 1) return end;
    Box cb;
    for (uint32_t i = begin; i < end; ++i) cb.extend(centroids[refs[i]]);
    const glm::vec3 extent = cb.hi - cb.lo;
    int axis = 0;
    if (extent.y > extent[axis]) axis = 1;
    if (extent.z > extent[axis]) axis = 2;
    auto median = [&]() {
      const uint32_t mid = begin + count / 2;
      std::nth_element(
          refs.begin() + begin, refs.begin() + mid, refs.begin() + end,
          [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
      return mid;
    };
    if (!(extent[axis] > 0.0f)) {  // every centroid in one point: only size forces a split
      return count > static_cast<uint32_t>(options.maxLeafSize) ? begin + count / 2 : end;
    }
    if (level >= kMedianSplitDepth)
      return count > static_cast<uint32_t>(options.maxLeafSize) ? median() : end;

    const int nb = options.bins;
    float bestCost = 1e30f;
    int bestAxis = -1, bestBin = -1;
    std::vector<Box> binBox(static_cast<size_t>(nb));
    std::vector<uint32_t> binCount(static_cast<size_t>(nb));
    std::vector<float> rightArea(static_cast<size_t>(nb));
    std::vector<uint32_t> rightCount(static_cast<size_t>(nb));
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0f)) continue;
      std::fill(binBox.begin(), binBox.end(), Box{});
      std::fill(binCount.begin(), binCount.end(), 0u);
      const float scale = static_cast<float>(nb) / extent[a];
      for (uint32_t i = begin; i < end; ++i) {
        const uint32_t t = refs[i];
        const int b = std::min(nb - 1, static_cast<int>((centroids[t][a] - cb.lo[a]) * scale));
        binBox[static_cast<size_t>(b)].extend(boxes[t]);
        ++binCount[static_cast<size_t>(b)];
      }
      Box r;
      uint32_t rc = 0;
      for (int b = nb - 1; b > 0; --b) {
        r.extend(binBox[static_cast<size_t>(b)]);
        rc += binCount[static_cast<size_t>(b)];
        rightArea[static_cast<size_t>(b)] = r.area();
        rightCount[static_cast<size_t>(b)] = rc;
      }
      Box l;
      uint32_t lc = 0;
      for (int b = 1; b < nb; ++b) {  // split between bin b-1 and b
        l.extend(binBox[static_cast<size_t>(b - 1)]);
        lc += binCount[static_cast<size_t>(b - 1)];
        if (lc == 0 || rightCount[static_cast<size_t>(b)] == 0) continue;
        const float cost = l.area() * static_cast<float>(lc) +
                           rightArea[static_cast<size_t>(b)] *
                               static_cast<float>(rightCount[static_cast<size_t>(b)]);
        if (cost < bestCost) {
          bestCost = cost;
          bestAxis = a;
          bestBin = b;
        }
      }
    }
    const float leafCost = static_cast<float>(count);
    const float area = std::max(box.area(), 1e-30f);
    const float splitCost = options.traversalCost + bestCost / area;
    if (bestAxis < 0) return count > static_cast<uint32_t>(options.maxLeafSize) ? median() : end;
    if (count <= static_cast<uint32_t>(options.maxLeafSize) && leafCost <= splitCost) return end;
    const float scale = static_cast<float>(nb) / extent[bestAxis];
    const float lo = cb.lo[bestAxis];
    auto mid = std::partition(refs.begin() + begin, refs.begin() + end, [&](uint32_t t) {
      const int b = std::min(nb - 1, static_cast<int>((centroids[t][bestAxis] - lo) * scale));
      return b < bestBin;
    });
    const auto m = static_cast<uint32_t>(mid - refs.begin());
    if (m == begin || m == end) return median();  // float rounding put everything on one side
    return m;
  }

  ChildRef build(uint32_t begin, uint32_t end, int level) {
    depth = std::max(depth, level);
    ChildRef ref;
    ref.box = boundsOf(begin, end);
    const uint32_t m = split(begin, end, ref.box, level);
    if (m == end) {
      ref.index = begin;
      ref.count = end - begin;
      sah += static_cast<double>(ref.box.area()) * ref.count;
      return ref;
    }
    const auto node = static_cast<uint32_t>(nodes.size());
    nodes.emplace_back();
    sah += static_cast<double>(ref.box.area()) * options.traversalCost;
    const ChildRef l = build(begin, m, level + 1);
    const ChildRef r = build(m, end, level + 1);
    nodes[node] = makeNode(l, r);
    ref.index = node;
    ref.count = 0;
    return ref;
  }

  static gpu::GpuBvhNode makeNode(const ChildRef& l, const ChildRef& r) {
    gpu::GpuBvhNode n{};
    n.leftMin = glm::vec4(l.box.lo, bitsToFloat(l.index));
    n.leftMax = glm::vec4(l.box.hi, bitsToFloat(l.count));
    n.rightMin = glm::vec4(r.box.lo, bitsToFloat(r.index));
    n.rightMax = glm::vec4(r.box.hi, bitsToFloat(r.count));
    return n;
  }
};

}  // namespace

bool intersectTriangle(const BvhRay& ray, const glm::vec3& v0, const glm::vec3& e1,
                       const glm::vec3& e2, float* t, float* u, float* v) {
  const glm::vec3 p = glm::cross(ray.direction, e2);
  const float det = glm::dot(e1, p);
  const float inv = 1.0f / det;
  const glm::vec3 s = ray.origin - v0;
  const float uu = glm::dot(s, p) * inv;
  const glm::vec3 q = glm::cross(s, e1);
  const float vv = glm::dot(ray.direction, q) * inv;
  const float tt = glm::dot(e2, q) * inv;
  // Written so that NaN (det == 0) fails every test.
  if (!(uu >= 0.0f && vv >= 0.0f && uu + vv <= 1.0f && tt > ray.tMin && tt < ray.tMax))
    return false;
  *t = tt;
  *u = uu;
  *v = vv;
  return true;
}

Bvh::Bvh(const std::vector<BvhTriangle>& triangles, const Options& options) {
  Builder b{triangles, options, {}, {}, {}, {}, 0, 0.0};
  const size_t n = triangles.size();
  b.boxes.resize(n);
  b.centroids.resize(n);
  b.refs.resize(n);
  std::iota(b.refs.begin(), b.refs.end(), 0u);
  for (size_t i = 0; i < n; ++i) {
    Box box;
    box.extend(triangles[i].v0);
    box.extend(triangles[i].v1);
    box.extend(triangles[i].v2);
    b.boxes[i] = box;
    b.centroids[i] = 0.5f * (box.lo + box.hi);
  }
  Builder::ChildRef root;
  if (n > 0) {
    root = b.build(0, static_cast<uint32_t>(n), 1);
  }
  // An interior root was allocated first, as node 0.
  if (n == 0 || root.count > 0) {
    // A single leaf (or nothing): wrap it so traversal always starts at node 0.
    b.nodes.insert(b.nodes.begin(), Builder::makeNode(root, Builder::ChildRef{}));
    b.depth = 2;
  }
  if (b.depth > static_cast<int>(gpu::kPtStackSize))
    throw Error(strf("BVH of %zu triangles is %d levels deep, more than the traversal stack (%u)",
                     n, b.depth, gpu::kPtStackSize));
  nodes_ = std::move(b.nodes);
  order_ = std::move(b.refs);
  depth_ = b.depth;
  Box all;
  for (const Box& box : b.boxes) all.extend(box);
  sah_ = all.area() > 0.0f ? b.sah / all.area() : 0.0;
  triangles_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const BvhTriangle& t = triangles[order_[i]];
    triangles_[i].v0 = glm::vec4(t.v0, 0.0f);
    triangles_[i].e1 = glm::vec4(t.v1 - t.v0, 0.0f);
    triangles_[i].e2 = glm::vec4(t.v2 - t.v0, 0.0f);
  }
}

template <bool kAnyHit>
bool Bvh::traverse(const BvhRay& ray, BvhHit* hit) const {
  if (nodes_.empty()) return false;
  const gpu::BvhArrays arrays{nodes_.data(), triangles_.data()};
  float t = 0.0f;
  uint32_t triangle = 0;
  glm::vec2 bary(0.0f);
  if (!gpu::bvhTrace(arrays, ray.origin, ray.direction, ray.tMin, ray.tMax, kAnyHit, t, triangle,
                     bary))
    return false;
  hit->t = t;
  hit->u = bary.x;
  hit->v = bary.y;
  hit->triangle = static_cast<int>(order_[triangle]);
  return true;
}

bool Bvh::intersect(const BvhRay& ray, BvhHit* hit) const {
  return traverse<false>(ray, hit);
}

bool Bvh::occluded(const BvhRay& ray) const {
  BvhHit unused;
  return traverse<true>(ray, &unused);
}

}  // namespace voxgi::render
