// Path tracer data as the GPU reads it (std430 SSBOs, one std140 uniform block),
// shared by C++ (src/render/bvh.*, src/render/pathtrace/pathtrace_pass.*) and GLSL
// (shaders/render/pathtrace.comp). Sizes and offsets are asserted here and checked
// against the linked program in tests/render/pathtrace_gltest.cpp.
//
// Integers that share a vec4 with floats are stored as their bit patterns
// (floatBitsToUint in GLSL, std::bit_cast in C++).
#ifndef VOXGI_PATHTRACE_SHARED_H
#define VOXGI_PATHTRACE_SHARED_H

#include "bindings_shared.h"
#include "gpu_types.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// Work group: 8x8 pixels (the kernel's local size). On llvmpipe a group runs on one
// thread, 8 lanes at a time.
VOXGI_CONST uint kPtGroupX = 8u;
VOXGI_CONST uint kPtGroupY = 8u;
VOXGI_CONST uint kPtStackSize = 48u;   // traversal stack (entries); the builder checks depth
VOXGI_CONST uint kPtMaxLeafSize = 1u;  // leaves hold one triangle: fastest on llvmpipe
// llvmpipe stops every loop of a shader invocation once the invocation has run
// 65535 loop iterations in all (LP_MAX_TGSI_LOOP_ITERATIONS, shared by all loops and
// counted per SIMD vector), silently. Past it a path would come back truncated and
// the image biased dark. So each dispatch traces one path per pixel, and a path
// that runs past this per-lane budget of loop iterations stops and is counted
// (the counter SSBO): the count is reported, and tests require it to be 0.
VOXGI_CONST uint kPtLoopBudget = 8192u;

// A BVH node stores the bounds of both children, so one fetch tests two boxes.
// Child reference: count == 0 -> interior node `index`; else a leaf of `count`
// triangles starting at `index`. Node 0 is the root, never a child: an interior
// reference to node 0 marks an empty child.
struct GpuBvhNode {
  vec4 leftMin;   // xyz bounds, w: left index (bits)
  vec4 leftMax;   // xyz bounds, w: left count (bits)
  vec4 rightMin;  // w: right index (bits)
  vec4 rightMax;  // w: right count (bits)
};

// Triangle in BVH order for intersection (Moeller-Trumbore): v0 and the two edges,
// and in their w what shading the hit needs besides the scene's own vertices: the
// material, the emitter pdf, and where the triangle's corners are in the scene's
// index buffer (GpuScene's vertices and indices, read through it: bvh_trace.glsl).
struct GpuPtTriangle {
  vec4 v0;  // w: material index (bits)
  vec4 e1;  // v1 - v0; w: emitter pdf per unit area of this triangle when sampled by
            // NEE (0: none), negated where rtgi lights it as part of a cluster
            // (scene::exactEmitterDraws): the path tracer reads its magnitude
  vec4 e2;  // v2 - v0; w: its first index in the scene's index buffer (bits)
};

// An emissive triangle for next-event estimation, chosen by power through a
// Walker alias table (Vose's construction).
// With an emissive texture, the radiance at a point is `radiance` times the texture
// there (read at the corner UVs interpolated); the probability of choosing a
// triangle then follows the texture's mean over it.
struct GpuPtEmissive {
  vec4 v0;        // w: alias acceptance probability
  vec4 e1;        // w: alias index (bits)
  vec4 e2;        // w: probability of choosing this triangle
  vec4 radiance;  // rgb: the material's emission (factor x strength), w: 1 if two-sided
  vec4 uv01;      // corner UVs 0 and 1
  vec4 uv2;       // xy corner UV 2, z: emissive texture + 1 (bits; 0: none), w: unused
};

struct GpuPtParams {
  vec4 cameraPosition;  // w: ray epsilon (scene-scaled)
  vec4 cameraRight;     // right * tan(fov/2) * aspect
  vec4 cameraUp;        // up * tan(fov/2)
  vec4 cameraForward;
  uvec4 image;     // x width, y height, z first sample index of this dispatch, w samples per pass
  uvec4 tile;      // x, y: tile origin in pixels; z seed; w: emissive triangle count
  uvec4 depth;     // x max depth (Mitsuba's convention), y roulette depth, z light count
  uvec4 reserved;  // unused
};

#ifdef __cplusplus
static_assert(sizeof(GpuBvhNode) == 64);
static_assert(offsetof(GpuBvhNode, rightMin) == 32);
static_assert(sizeof(GpuPtTriangle) == 48);
static_assert(sizeof(GpuPtEmissive) == 96);
static_assert(offsetof(GpuPtEmissive, radiance) == 48);
static_assert(sizeof(GpuPtParams) == 128);
static_assert(offsetof(GpuPtParams, image) == 64);
static_assert(offsetof(GpuPtParams, depth) == 96);
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_PATHTRACE_SHARED_H
