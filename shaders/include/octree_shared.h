// Sparse voxel octree layout shared by C++ (src/voxel/octree.*) and GLSL.
//
// The root cube holds 2^depth voxels a side over the voxel grid's origin (the grid's
// N <= 2^depth; voxels past N are empty). Node 0 is the root. Every node has one
// 32-bit word in `nodes`:
//   inner node: 0 = empty (no occupied voxel below it), else the index of its first
//               child; the 8 children are contiguous (a tile), child c = x | y<<1 | z<<2
//               of the bit of the voxel coordinate at that level;
//   leaf (level == depth): 0 = empty, kOctreeLeafOccupied = an occupied voxel.
// Per-node data lives in parallel arrays indexed by the node:
//   radiance: rgb9e5 (shared exponent, 4 bytes): outgoing diffuse radiance reflected
//             by the voxel (light injected, plus bounces): the running mean of the
//             estimates so far, published for tracing;
//   mean:     rgba32f, leaves only: that running mean at full precision (refinement);
//   material: rgba8 albedo + opacity (coverage), rgba8 snorm normal (0 where two
//             sides cancel);
//   emission: rgb9e5 emitted radiance.
// The light buffers (radiance, mean, and those of the refinement and the bounces)
// have one slot a node and, past them, one for the - side of each two-sided leaf
// (octree.glsl, leafAxis), whose normal word holds that slot's index in place of
// its normal.
// Inner nodes hold their children filtered for cone tracing: opacity is the mean of
// the 8 children's (an empty child counts 0) and colours are opacity-weighted means
// (Crassin & Green, "Octree-Based Sparse Voxelization Using the GPU Hardware
// Rasterizer", OpenGL Insights ch. 22, 2012).
#ifndef VOXGI_OCTREE_SHARED_H
#define VOXGI_OCTREE_SHARED_H

#include "bindings_shared.h"
#include "gpu_types.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

VOXGI_CONST uint kOctreeMaxDepth = 9u;  // 512^3
VOXGI_CONST uint kOctreeLeafOccupied = 0x80000000u;
VOXGI_CONST uint kOctreeGroupSize = 64u;

struct OctreeParams {
  vec4 origin;  // xyz world corner of the root cube, w voxel size
  uvec4 info;   // x depth, y root size in voxels (2^depth), z grid resolution N, w node capacity
  uvec4 pass;   // x level (build/filter), y first node of the level, z nodes in the level, w seed
  uvec4 light;  // x rays per voxel (inject / bounce), y light count, z emitter count, w bounce
  uvec4 slice;  // inject, bounce, average: the voxel list from x on (a refinement slice's)
  vec4 blend;   // x: weight of this estimate in the running mean (octree_average.comp);
                // y: 1 when the estimate has voxel bounces beside its direct light;
                // z: 1 to keep the bounces' mean apart (Settings::keepBounces)
  uvec4 sides;  // x: the first of the two-sided leaves' - side slots in the light
                // buffers (octree.glsl, backSlot); yzw 0
  uvec4 rays;   // x: the bounce pass's rays (octree_bounce.comp): kOctreeRaysTraced,
                // kOctreeRaysRecorded or kOctreeRaysReplayed; yzw 0
};

// octree_bounce.comp's rays (OctreeParams::rays.x): traced; traced and their hits
// recorded (kOctreeReplayBinding); or the recorded hits read again, none traced.
VOXGI_CONST uint kOctreeRaysTraced = 0u;
VOXGI_CONST uint kOctreeRaysRecorded = 1u;
VOXGI_CONST uint kOctreeRaysReplayed = 2u;

// Written by the build passes; read back once per build.
struct OctreeCounters {
  uint nodeCount;  // nodes allocated (root included)
  uint overflow;   // allocations refused for lack of capacity
  uint twoSided;   // two-sided leaves (octree_fill.comp): their second light slots
  uint pad1;
  uint levelStart[12];  // first node of each level; levelStart[depth + 1] = nodeCount
};

// A ray for octree_raycast.comp, in voxels of the root cube.
struct OctreeRay {
  vec4 origin;     // w: where the ray ends (t)
  vec4 direction;  // w: where it starts (t)
  vec4 invDirection;
};

#ifdef __cplusplus
static_assert(sizeof(OctreeRay) == 48);
static_assert(sizeof(OctreeParams) == 128);
static_assert(sizeof(OctreeCounters) == 64);
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_OCTREE_SHARED_H
