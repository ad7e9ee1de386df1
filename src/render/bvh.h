// Bounding volume hierarchy over the scene's exact triangles, for the path tracer.
//
// Built on the CPU by binned SAH (Wald 2007, "On fast construction of SAH-based
// bounding volume hierarchies": 16 bins per axis over the centroid bounds, leaf when
// no split is cheaper than the leaf) on every core, the same tree bit for bit as a
// one-thread recursive build (bvh.cpp says how), flattened into the layout of
// shaders/include/pathtrace_shared.h: each node holds both children's bounds, so the
// GPU tests two boxes per fetch and visits the nearer child first. Triangles are
// reordered so every leaf is a contiguous run; order()[i] is the input index of the
// i-th triangle in BVH order.
//
// The CPU traversal is the shaders' own (bvh_shared.h, built as C++) over the same
// flattened nodes; the tests check it against brute force (tests/render/bvh_test.cpp).
#ifndef VOXGI_RENDER_BVH_H
#define VOXGI_RENDER_BVH_H

#include <cstdint>
#include <functional>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "bvh_shared.h"
#include "pathtrace_shared.h"

namespace voxgi::render {

// Leaves new elements uninitialised: resize() writes nothing, so that memory is
// first touched by what fills it.
template <typename T>
struct UninitializedAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <typename U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
using BvhNodes = std::vector<gpu::GpuBvhNode, UninitializedAllocator<gpu::GpuBvhNode>>;

struct BvhTriangle {
  glm::vec3 v0, v1, v2;
};

struct BvhRay {
  glm::vec3 origin;
  glm::vec3 direction;  // need not be unit length; t is in its units
  float tMin = 0.0f;
  float tMax = 1e30f;
};

struct BvhHit {
  float t = 0.0f;
  float u = 0.0f, v = 0.0f;  // barycentrics of v1 and v2
  int triangle = -1;         // input index
};

// Moeller-Trumbore; the same arithmetic as the shader. Both faces hit.
bool intersectTriangle(const BvhRay& ray, const glm::vec3& v0, const glm::vec3& e1,
                       const glm::vec3& e2, float* t, float* u, float* v);

class Bvh {
 public:
  struct Options {
    // A leaf never holds more; the GPU tests exactly kPtMaxLeafSize per leaf.
    int maxLeafSize = static_cast<int>(gpu::kPtMaxLeafSize);
    float traversalCost = 1.0f;  // SAH cost of visiting a node, relative to one triangle test
    int bins = 16;
    // false: the build makes the nodes and the order only, not gpuTriangles(), and
    // no ray may be traced (GpuBvh writes the triangles into its buffer itself).
    bool keepTriangles = true;
  };

  Bvh() = default;
  explicit Bvh(const std::vector<BvhTriangle>& triangles, const Options& options);
  // The same from `count` triangles that `triangle(i)` returns (read from each
  // triangle's source, such as a scene's vertices and indices, with no array of
  // them kept: GpuBvh), called from several threads at once.
  Bvh(size_t count, const std::function<BvhTriangle(size_t)>& triangle, const Options& options);
  explicit Bvh(const std::vector<BvhTriangle>& triangles) : Bvh(triangles, Options{}) {}

  // A triangle as the GPU reads it: v0 and two edges.
  static gpu::GpuPtTriangle gpuTriangle(const BvhTriangle& t) {
    return {glm::vec4(t.v0, 0.0f), glm::vec4(t.v1 - t.v0, 0.0f), glm::vec4(t.v2 - t.v0, 0.0f)};
  }

  // Closest hit in (tMin, tMax); false when nothing is hit.
  bool intersect(const BvhRay& ray, BvhHit* hit) const;
  // Any hit in (tMin, tMax).
  bool occluded(const BvhRay& ray) const;

  const BvhNodes& nodes() const { return nodes_; }
  const std::vector<uint32_t>& order() const { return order_; }
  // BVH-ordered triangles as the GPU reads them.
  const std::vector<gpu::GpuPtTriangle>& gpuTriangles() const { return triangles_; }

  int depth() const { return depth_; }     // deepest node, root = 1
  double sahCost() const { return sah_; }  // expected cost of a random ray, in triangle tests
  size_t triangleCount() const { return count_; }

  // The flattened arrays, moved out for an upload that keeps no CPU copy. Only the
  // counts, depth and SAH cost are left: no ray may be traced afterwards.
  struct Arrays {
    BvhNodes nodes;
    std::vector<uint32_t> order;
    std::vector<gpu::GpuPtTriangle> triangles;
  };
  Arrays release();

 private:
  struct Child {
    glm::vec3 lo{1.0f}, hi{-1.0f};
    uint32_t index = 0, count = 0;
  };
  template <bool kAnyHit>
  bool traverse(const BvhRay& ray, BvhHit* hit) const;

  BvhNodes nodes_;
  std::vector<uint32_t> order_;
  std::vector<gpu::GpuPtTriangle> triangles_;  // BVH order
  size_t count_ = 0;
  int depth_ = 0;
  double sah_ = 0.0;
};

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_BVH_H
