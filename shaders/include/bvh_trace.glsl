// BVH traversal over the scene's exact triangles (src/render/gpu_bvh.h), shared by
// the path tracer (pathtrace.comp) and rtgi's rays (rtgi_bvh.glsl): the node and
// triangle reads from buffer textures, the attributes at a hit, and the traversal
// of bvh_shared.h (which the CPU BVH runs too).
// Include after pathtrace_shared.h. The including shader declares what this reads:
//   usamplerBuffer nodeTexels, triangleTexels   the BVH (RGBA32UI buffer textures)
//   uint loopBudget   loop iterations the invocation may still run (kPtLoopBudget);
//                     every node visited spends one
//   const float kInf = 1.0 / 0.0
#ifndef VOXGI_BVH_TRACE_GLSL
#define VOXGI_BVH_TRACE_GLSL

// Node and triangle i from their buffer textures (see pathtrace_shared.h).
GpuBvhNode loadNode(uint i) {
  int b = int(i) * 4;
  GpuBvhNode n;
  n.leftMin = uintBitsToFloat(texelFetch(nodeTexels, b));
  n.leftMax = uintBitsToFloat(texelFetch(nodeTexels, b + 1));
  n.rightMin = uintBitsToFloat(texelFetch(nodeTexels, b + 2));
  n.rightMax = uintBitsToFloat(texelFetch(nodeTexels, b + 3));
  return n;
}
GpuPtTriangle loadTriangle(uint i) {
  int b = int(i) * 3;
  GpuPtTriangle t;
  t.v0 = uintBitsToFloat(texelFetch(triangleTexels, b));
  t.e1 = uintBitsToFloat(texelFetch(triangleTexels, b + 1));
  t.e2 = uintBitsToFloat(texelFetch(triangleTexels, b + 2));
  return t;
}

#ifdef VOXGI_BVH_UVS
// Texture coordinates at barycentrics bc of triangle tri, from the corner UVs in
// `usamplerBuffer uvTexels` (two RGBA32UI texels a triangle, BVH order), which the
// including shader declares when it defines VOXGI_BVH_UVS. Channel 0 first; in a
// scene with a channel 1 (scene::Vertex::uv2) its corners follow, as many again.
vec2 triangleUvAt(int b, vec2 bc) {
  vec4 a = uintBitsToFloat(texelFetch(uvTexels, b));
  vec2 c = uintBitsToFloat(texelFetch(uvTexels, b + 1).xy);
  return (1.0 - bc.x - bc.y) * a.xy + bc.x * a.zw + bc.y * c;
}
vec2 triangleUv(uint tri, vec2 bc) { return triangleUvAt(int(tri) * 2, bc); }
// Channel 1; read only for materials that set a kMaterial*Uv2 bit, which only
// scenes with the second half have.
vec2 triangleUv2(uint tri, vec2 bc) {
  return triangleUvAt(textureSize(uvTexels) / 2 + int(tri) * 2, bc);
}
#endif

#ifdef VOXGI_BVH_COLORS
// The vertex colour (COLOR_0) at barycentrics bc of triangle tri, from its corners'
// colours (three a triangle, BVH order; scene side: render/gpu_bvh.h), an SSBO at the
// binding VOXGI_BVH_COLOR_BINDING, which the including shader defines.
layout(std430, binding = VOXGI_BVH_COLOR_BINDING) readonly buffer BvhColors {
  vec4 bvhCornerColors[];
};
vec4 triangleColor(uint tri, vec2 bc) {
  uint b = tri * 3u;
  return (1.0 - bc.x - bc.y) * bvhCornerColors[b] + bc.x * bvhCornerColors[b + 1u] +
         bc.y * bvhCornerColors[b + 2u];
}
#endif

#ifdef VOXGI_BVH_TANGENTS
// The tangent (xyz, w handedness) at barycentrics bc of triangle tri, from its
// corners' tangents (three a triangle, BVH order; scene side: render/gpu_bvh.h), an
// SSBO at the binding VOXGI_BVH_TANGENT_BINDING, which the including shader defines.
layout(std430, binding = VOXGI_BVH_TANGENT_BINDING) readonly buffer BvhTangents {
  vec4 bvhCornerTangents[];
};
vec4 triangleTangent(uint tri, vec2 bc) {
  uint b = tri * 3u;
  return (1.0 - bc.x - bc.y) * bvhCornerTangents[b] + bc.x * bvhCornerTangents[b + 1u] +
         bc.y * bvhCornerTangents[b + 2u];
}
#endif

#ifdef VOXGI_BVH_ALPHA
// With VOXGI_BVH_ALPHA, a candidate hit counts only where this returns true (the
// including shader defines it: alpha masks, texture_shared.h's alphaStops).
bool bvhHitStops(uint tri, vec2 bc);
#endif

// --- ray casting (bvh_shared.h) ---------------------------------------------------
#include "bvh_shared.h"

// Closest hit (anyHit false) or any hit in (0, tMax).
bool trace(vec3 o, vec3 d, float tMax, bool anyHit, out float tHit, out uint triHit,
           out vec2 bary) {
  return bvhTrace(o, d, 0.0, tMax, anyHit, tHit, triHit, bary);
}

bool occluded(vec3 o, vec3 d, float tMax) {
  float t;
  uint tri;
  vec2 b;
  return trace(o, d, tMax, true, t, tri, b);
}

#endif  // VOXGI_BVH_TRACE_GLSL
