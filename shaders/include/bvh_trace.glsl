// BVH traversal over the scene's exact triangles (src/render/gpu_bvh.h), shared by
// the path tracer (pathtrace.comp) and rtgi's rays (rtgi_bvh.glsl): the node and
// triangle reads from buffer textures, the attributes at a hit, and the traversal
// of bvh_shared.h (which the CPU BVH runs too).
// Include after pathtrace_shared.h. The including shader declares what this reads:
//   usamplerBuffer nodeTexels, triangleTexels   the BVH (RGBA32UI buffer textures)
//   samplerBuffer sceneVertexTexels   the scene's vertex buffer (scene::Vertex as
//                     five RG32F texels a vertex: position, normal, uv, uv2)
//   uint sceneIndices[]   the scene's index buffer (an SSBO), which a triangle's
//                     record points into (GpuPtTriangle: its first index in e2.w)
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

// What a hit needs besides its position, from the triangle's record and the scene's
// own vertices (GpuScene's buffers, no copy in BVH order): the material, the
// emitter pdf, the corners' vertex indices and their attributes at barycentrics bc.
uint triangleMaterial(uint tri) { return texelFetch(triangleTexels, int(tri) * 3).w; }
float triangleEmitterPdf(uint tri) {
  return uintBitsToFloat(texelFetch(triangleTexels, int(tri) * 3 + 1).w);
}
uvec3 triangleCorners(uint tri) {
  uint first = texelFetch(triangleTexels, int(tri) * 3 + 2).w;
  return uvec3(sceneIndices[first], sceneIndices[first + 1u], sceneIndices[first + 2u]);
}
vec3 vertexNormal(uint v) {
  vec2 a = texelFetch(sceneVertexTexels, int(v) * 5 + 1).xy;
  vec2 b = texelFetch(sceneVertexTexels, int(v) * 5 + 2).xy;
  return vec3(a.y, b);
}
// The corners' normals interpolated (not normalized).
vec3 triangleNormal(uint tri, vec2 bc) {
  uvec3 c = triangleCorners(tri);
  return (1.0 - bc.x - bc.y) * vertexNormal(c.x) + bc.x * vertexNormal(c.y) +
         bc.y * vertexNormal(c.z);
}

#ifdef VOXGI_BVH_UVS
// Texture coordinates at barycentrics bc of triangle tri: channel 0, and channel 1
// (scene::Vertex::uv2, equal to uv where a material has none).
vec2 vertexTexels(uvec3 c, vec2 bc, int slot) {
  return (1.0 - bc.x - bc.y) * texelFetch(sceneVertexTexels, int(c.x) * 5 + slot).xy +
         bc.x * texelFetch(sceneVertexTexels, int(c.y) * 5 + slot).xy +
         bc.y * texelFetch(sceneVertexTexels, int(c.z) * 5 + slot).xy;
}
vec2 triangleUv(uint tri, vec2 bc) { return vertexTexels(triangleCorners(tri), bc, 3); }
vec2 triangleUv2(uint tri, vec2 bc) { return vertexTexels(triangleCorners(tri), bc, 4); }
#endif

#ifdef VOXGI_BVH_COLORS
// The vertex colour (COLOR_0) at barycentrics bc of triangle tri, from the scene's
// colour buffer (vec4 per vertex), an SSBO at the binding VOXGI_BVH_COLOR_BINDING,
// which the including shader defines.
layout(std430, binding = VOXGI_BVH_COLOR_BINDING) readonly buffer BvhColors { vec4 sceneColors[]; };
vec4 triangleColor(uint tri, vec2 bc) {
  uvec3 c = triangleCorners(tri);
  return (1.0 - bc.x - bc.y) * sceneColors[c.x] + bc.x * sceneColors[c.y] + bc.y * sceneColors[c.z];
}
#endif

#ifdef VOXGI_BVH_TANGENTS
// The tangent (xyz, w handedness) at barycentrics bc of triangle tri, from the scene's
// tangent buffer (vec4 per vertex), an SSBO at the binding VOXGI_BVH_TANGENT_BINDING,
// which the including shader defines.
layout(std430, binding = VOXGI_BVH_TANGENT_BINDING) readonly buffer BvhTangents {
  vec4 sceneTangents[];
};
vec4 triangleTangent(uint tri, vec2 bc) {
  uvec3 c = triangleCorners(tri);
  return (1.0 - bc.x - bc.y) * sceneTangents[c.x] + bc.x * sceneTangents[c.y] +
         bc.y * sceneTangents[c.z];
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
