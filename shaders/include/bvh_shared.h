// BVH traversal over the scene's exact triangles, written once in the common subset
// of GLSL and C++ (shared_fn.h): the path tracer (pathtrace.comp) and rtgi's rays
// (rtgi_bvh.glsl) run it through bvh_trace.glsl, the CPU BVH (render::Bvh, which
// builds the tree: src/render/bvh.h) runs the C++ build. Twin test:
// tests/render/bvh_twin_gltest.cpp.
//
// GLSL: the including shader defines, before the include,
//   GpuBvhNode loadNode(uint i), GpuPtTriangle loadTriangle(uint i)   node and
//       triangle i (BVH order; see pathtrace_shared.h)
//   uint loopBudget   loop iterations the invocation may still run (kPtLoopBudget);
//                     every node visited spends one
//   const float kInf = 1.0 / 0.0
// and, with VOXGI_BVH_ALPHA, bool bvhHitStops(uint tri, vec2 bc): a candidate hit
// counts only where it returns true (alpha masks). C++ passes the arrays (BvhArrays)
// and has no loop budget.
#ifndef VOXGI_BVH_SHARED_H
#define VOXGI_BVH_SHARED_H

#include "pathtrace_shared.h"
#include "shared_fn.h"

#ifdef __cplusplus
#include <limits>
namespace voxgi::gpu {
VOXGI_CONST float kInf = std::numeric_limits<float>::infinity();
struct BvhArrays {
  const GpuBvhNode* nodes;
  const GpuPtTriangle* triangles;
};
#define VOXGI_BVH_PARAM const BvhArrays &bvh,
#define VOXGI_BVH_ARG bvh,
#define VOXGI_BVH_NODE(i) bvh.nodes[i]
#define VOXGI_BVH_TRIANGLE(i) bvh.triangles[i]
#define VOXGI_BVH_BUDGET_LEFT true
#define VOXGI_BVH_SPEND()
#else
#define VOXGI_BVH_PARAM
#define VOXGI_BVH_ARG
#define VOXGI_BVH_NODE(i) loadNode(i)
#define VOXGI_BVH_TRIANGLE(i) loadTriangle(i)
#define VOXGI_BVH_BUDGET_LEFT (loopBudget > 0u)
#define VOXGI_BVH_SPEND() --loopBudget
#endif

// Slab test against one box: the distance at which the ray enters it within
// [tMin, tMax], or kInf on a miss.
VOXGI_FN float bvhHitBox(vec3 lo, vec3 hi, vec3 o, vec3 inv, float tMin, float tMax) {
  vec3 t0 = (lo - o) * inv;
  vec3 t1 = (hi - o) * inv;
  vec3 tn = min(t0, t1);
  vec3 tf = max(t0, t1);
  float tEnter = max(max(tn.x, tn.y), max(tn.z, tMin));
  float tExit = min(min(tf.x, tf.y), min(tf.z, tMax));
  return tEnter <= tExit ? tEnter : kInf;
}

// The closest hit (anyHit false), or any hit, in (tMin, tMax) of the ray o + t d:
// its distance, triangle (BVH order) and barycentrics (u, v). Short-stack traversal
// of the two-children nodes: descend into the nearer child, push the farther one.
// Triangles by Moeller-Trumbore; NaN (a ray in a triangle's plane) fails every test.
VOXGI_FN bool bvhTrace(VOXGI_BVH_PARAM vec3 o, vec3 d, float tMin, float tMax, bool anyHit,
                       VOXGI_OUT(float) tHit, VOXGI_OUT(uint) triHit, VOXGI_OUT(vec2) bary) {
  tHit = tMax;
  triHit = 0u;
  bary = vec2(0.0f);
  bool found = false;
  vec3 safe = vec3(abs(d.x) > 1e-20f ? d.x : 1e-20f, abs(d.y) > 1e-20f ? d.y : 1e-20f,
                   abs(d.z) > 1e-20f ? d.z : 1e-20f);
  vec3 inv = 1.0f / safe;
  uint stack[kPtStackSize];
  int sp = 0;
  uint node = 0u;
  while (VOXGI_BVH_BUDGET_LEFT) {
    VOXGI_BVH_SPEND();
    GpuBvhNode n = VOXGI_BVH_NODE(node);
    float tl = bvhHitBox(vec3(n.leftMin), vec3(n.leftMax), o, inv, tMin, tHit);
    float tr = bvhHitBox(vec3(n.rightMin), vec3(n.rightMax), o, inv, tMin, tHit);
    uint li = floatBitsToUint(n.leftMin.w);
    uint lc = floatBitsToUint(n.leftMax.w);
    uint ri = floatBitsToUint(n.rightMin.w);
    uint rc = floatBitsToUint(n.rightMax.w);
    for (int side = 0; side < 2; ++side) {
      uint first = side == 0 ? li : ri;
      uint count = side == 0 ? lc : rc;
      float tb = side == 0 ? tl : tr;
      if (count == 0u || tb == kInf) continue;
      // A fixed trip count: unrolled, so it does not spend a driver's loop budget.
      for (uint j = 0u; j < kPtMaxLeafSize; ++j) {
        if (j >= count) break;
        uint i = first + j;
        GpuPtTriangle t = VOXGI_BVH_TRIANGLE(i);
        vec3 e1 = vec3(t.e1);
        vec3 e2 = vec3(t.e2);
        vec3 p = cross(d, e2);
        float invDet = 1.0f / dot(e1, p);
        vec3 s = o - vec3(t.v0);
        float u = dot(s, p) * invDet;
        vec3 q = cross(s, e1);
        float v = dot(d, q) * invDet;
        float th = dot(e2, q) * invDet;
        if (u >= 0.0f && v >= 0.0f && u + v <= 1.0f && th > tMin && th < tHit
#ifdef VOXGI_BVH_ALPHA
            && bvhHitStops(i, vec2(u, v))
#endif
        ) {
          tHit = th;
          triHit = i;
          bary = vec2(u, v);
          found = true;
        }
      }
      if (anyHit && found) return true;
    }
    bool goL = lc == 0u && li != 0u && tl < tHit;  // node 0 as a child: empty
    bool goR = rc == 0u && ri != 0u && tr < tHit;
    if (goL && goR) {
      bool rFirst = tr < tl;
      node = rFirst ? ri : li;
      stack[sp++] = rFirst ? li : ri;
    } else if (goL) {
      node = li;
    } else if (goR) {
      node = ri;
    } else {
      if (sp == 0) break;
      node = stack[--sp];
    }
  }
  return found;
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_BVH_SHARED_H
