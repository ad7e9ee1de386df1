// Ray marching through the sparse voxel octree (octree_shared.h), written once in
// the common subset of GLSL and C++: shaders include it through octree.glsl, which
// first defines VOXGI_NODE(i) to read the node words (from the buffer texture
// `octreeNodeTex`, or from the buffer `octreeNodes[]` in shaders that write nodes);
// C++ passes the nodes as a pointer. The C++ compile is the twin that
// tests/voxel/octree_gltest.cpp includes and checks against a plain dense-grid DDA.
//
// Method: a restart-free walk with a stack of the current voxel's ancestors (a
// "short stack" of depth + 1 entries, cf. Laine & Karras, "Efficient Sparse Voxel
// Octrees", 2010). At each step the walk descends from the deepest ancestor still
// valid to the deepest node containing the current voxel; an empty node of size s
// is skipped whole: the ray leaves its cube through the face it crosses first.
//
// Exactness: the walk reproduces a unit-step DDA voxel for voxel. Every plane
// crossing time is computed by one expression, marchPlaneT (precise: no fused
// multiply-add), and crossings are ordered by (t, axis), ties going to the lower
// axis, as the DDA does. Leaving an empty cube, the walk puts each other axis in
// the voxel the DDA would have reached by that crossing: a guess from the position,
// corrected by comparing plane crossing times exactly. So rays parallel to axes,
// along voxel edges and through corners give the DDA's first hit (tested on
// 10,000+ rays in tests/voxel/octree_gltest.cpp).
//
// Coordinates are in voxels of the root cube (origin at its corner); t is in units
// of |d|.
#ifndef VOXGI_OCTREE_MARCH_H
#define VOXGI_OCTREE_MARCH_H

#include "octree_shared.h"
#include "shared_fn.h"

#ifdef __cplusplus
#include <glm/gtc/bitfield.hpp>
#include <glm/integer.hpp>
namespace voxgi::gpu {
using ivec3 = glm::ivec3;
using uvec3 = glm::uvec3;
using bvec3 = glm::bvec3;
using glm::equal;
using glm::findMSB;
using glm::greaterThan;
using glm::lessThan;
using glm::notEqual;
#define VOXGI_NODES_PARAM const uint *octreeNodes,
#define VOXGI_NODES_ARG octreeNodes,
#define VOXGI_NODE(i) octreeNodes[i]
#else
#define VOXGI_NODES_PARAM
#define VOXGI_NODES_ARG
#endif

VOXGI_CONST float kMarchInf = 3.0e38;

struct MarchRay {
  vec3 o;         // origin, voxels
  vec3 d;         // direction (need not be unit)
  vec3 invD;      // 1 / d per axis, 0 where d is 0
  ivec3 stepDir;  // sign of d: -1, 0, +1
  float tEnd;     // the ray ends here
};

struct MarchState {
  ivec3 voxel;  // current voxel
  float t;      // where the ray entered it (or started)
};

struct MarchHit {
  bool hit;
  ivec3 voxel;
  uint node;  // the leaf
  float t;    // entry into the voxel
  int steps;  // cells visited
};

// invD is passed in so a test can give GLSL and C++ the same bits.
VOXGI_FN MarchRay marchRay(vec3 o, vec3 d, vec3 invD, float tEnd) {
  MarchRay r;
  r.o = o;
  r.d = d;
  r.tEnd = tEnd;
  for (int a = 0; a < 3; ++a) {
    r.stepDir[a] = d[a] > 0.0f ? 1 : (d[a] < 0.0f ? -1 : 0);
    r.invD[a] = r.stepDir[a] != 0 ? invD[a] : 0.0f;
  }
  return r;
}

// When the ray crosses the plane `coordinate` = plane of axis a.
VOXGI_FN float marchPlaneT(MarchRay r, int a, int plane) {
  VOXGI_PRECISE float t = (float(plane) - r.o[a]) * r.invD[a];
  return t;
}

// Clips [tStart, r.tEnd] to the root cube of `size` voxels and finds the first voxel.
VOXGI_FN bool marchBegin(MarchRay r, float tStart, int size, VOXGI_OUT(MarchState) s) {
  float t0 = tStart;
  float t1 = r.tEnd;
  for (int a = 0; a < 3; ++a) {
    if (r.stepDir[a] == 0) {
      if (!(r.o[a] >= 0.0f && r.o[a] < float(size))) return false;
    } else {
      float ta = marchPlaneT(r, a, 0);
      float tb = marchPlaneT(r, a, size);
      t0 = max(t0, min(ta, tb));
      t1 = min(t1, max(ta, tb));
    }
  }
  s.t = t0;
  s.voxel = ivec3(0);
  if (!(t0 <= t1)) return false;
  vec3 p = r.o + r.d * t0;
  s.voxel = clamp(ivec3(floor(p)), ivec3(0), ivec3(size - 1));
  return true;
}

// When the ray crosses each axis's plane `planes` (per component, as marchPlaneT).
VOXGI_FN vec3 marchPlanesT(MarchRay r, ivec3 planes) {
  VOXGI_PRECISE vec3 t = (vec3(planes) - r.o) * r.invD;
  return t;
}

// Per component: whether a crossing at t on that axis comes before the crossing at
// exitT on `axis` (ties: the lower axis first, as the DDA steps).
VOXGI_FN uvec3 marchBefore(vec3 t, float exitT, int axis) {
  return uvec3(lessThan(t, vec3(exitT))) |
         (uvec3(equal(t, vec3(exitT))) & uvec3(lessThan(ivec3(0, 1, 2), ivec3(axis))));
}

// Moves s to the voxel a unit DDA reaches as it leaves the aligned cube of
// `cellSize` voxels holding s.voxel. False when the ray ends or leaves the root cube.
// Written with vector operations and no loops: on a SIMD software rasterizer this
// is most of a step's cost.
VOXGI_FN bool marchExitCell(MarchRay r, int cellSize, int rootSize, VOXGI_INOUT(MarchState) s) {
  ivec3 base = s.voxel & ivec3(-cellSize);
  ivec3 up = ivec3(greaterThan(r.stepDir, ivec3(0)));  // 1 on axes the ray climbs
  uvec3 moving = uvec3(notEqual(r.stepDir, ivec3(0)));
  vec3 tExit = mix(vec3(kMarchInf), marchPlanesT(r, base + up * cellSize), bvec3(moving));
  int axis = (tExit.x <= tExit.y && tExit.x <= tExit.z) ? 0 : (tExit.y <= tExit.z ? 1 : 2);
  float exitT = axis == 0 ? tExit.x : (axis == 1 ? tExit.y : tExit.z);
  if (!(exitT <= r.tEnd)) return false;
  bvec3 isAxis = equal(ivec3(0, 1, 2), ivec3(axis));
  // On the exit axis: the voxel across the face.
  ivec3 across = base + up * (cellSize + 1) - 1;
  // On the others: where the DDA is by then. A guess from the position, clamped to
  // the part of the cube still ahead, then corrected by one voxel either way by
  // comparing exact crossing times (the guess is never further off).
  ivec3 first = s.voxel;
  ivec3 last = base + up * (cellSize - 1);
  ivec3 c = clamp(ivec3(floor(r.o + r.d * exitT)), min(first, last), max(first, last));
  uvec3 forward =
      marchBefore(marchPlanesT(r, c + up), exitT, axis) & moving & uvec3(notEqual(c, last));
  c += r.stepDir * ivec3(forward);
  uvec3 back = (uvec3(1u) - marchBefore(marchPlanesT(r, c + 1 - up), exitT, axis)) & moving &
               uvec3(notEqual(c, first));
  c -= r.stepDir * ivec3(back);
  c = mix(s.voxel, c, bvec3(moving));
  ivec3 v = mix(c, across, isAxis);
  int a = axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
  if (a < 0 || a >= rootSize) return false;
  s.voxel = v;
  s.t = exitT;
  return true;
}

// The first occupied leaf from s on, within maxSteps cells (a miss past them).
// On a hit, s is at the leaf: marchExitCell(r, 1, ...) then resumes past it.
VOXGI_FN MarchHit octreeFirstHit(VOXGI_NODES_PARAM MarchRay r, int depth, VOXGI_INOUT(MarchState) s,
                                 int maxSteps) {
  MarchHit h;
  h.hit = false;
  h.voxel = s.voxel;
  h.node = 0u;
  h.t = s.t;
  h.steps = 0;
  int rootSize = 1 << depth;
  uint stack[kOctreeMaxDepth + 1u];
  stack[0] = 0u;
  int valid = 0;
  while (h.steps < maxSteps) {
    ++h.steps;
    // Descend to the deepest node holding the voxel: one node word read per level.
    uint node = stack[valid];
    int level = valid;
    uint word = VOXGI_NODE(node);
    while (level < depth && word != 0u) {
      int shift = depth - 1 - level;
      uint child = uint((s.voxel.x >> shift) & 1) | (uint((s.voxel.y >> shift) & 1) << 1) |
                   (uint((s.voxel.z >> shift) & 1) << 2);
      node = word + child;
      ++level;
      stack[level] = node;
      word = VOXGI_NODE(node);
    }
    if (word != 0u) {  // only a leaf (level == depth) can be nonzero here
      h.hit = true;
      h.voxel = s.voxel;
      h.node = node;
      h.t = s.t;
      return h;
    }
    ivec3 old = s.voxel;
    if (!marchExitCell(r, 1 << (depth - level), rootSize, s)) break;
    int diff = (old.x ^ s.voxel.x) | (old.y ^ s.voxel.y) | (old.z ^ s.voxel.z);
    valid = min(level, depth - 1 - findMSB(diff));
  }
  h.voxel = s.voxel;
  h.t = s.t;
  return h;
}

// The node at `level` (or the empty ancestor above it) holding voxel v; `reached`
// says which level the descent stopped at.
VOXGI_FN uint octreeLookup(VOXGI_NODES_PARAM int depth, ivec3 v, int level,
                           VOXGI_OUT(int) reached) {
  uint node = 0u;
  int l = 0;
  while (l < level) {
    uint first = VOXGI_NODE(node);
    if (first == 0u) break;
    int shift = depth - 1 - l;
    uint child = uint((v.x >> shift) & 1) | (uint((v.y >> shift) & 1) << 1) |
                 (uint((v.z >> shift) & 1) << 2);
    node = first + child;
    ++l;
  }
  reached = l;
  return node;
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_OCTREE_MARCH_H
