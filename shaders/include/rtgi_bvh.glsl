// The scene's exact triangles for rtgi's rays (RTGI_BVH; render/gpu_bvh.h): the BVH's
// bindings, its traversal (bvh_trace.glsl), the ray offset off a triangle and shadow
// rays. RTGI_BVH_TEXTURES (a textured BVH): the material's textures at a hit, read as
// the path tracer reads them (bilinear, no mipmaps). RTGI_BVH_COLORS: the vertex
// colours at a hit. RTGI_BVH_TANGENTS: the tangents at a hit (normal maps).
// RTGI_BVH_ALPHA (the scene has alpha-masked materials): a hit on a
// masked-out texel does not stop a ray, as in the path tracer. RTGI_BVH_CULL
// (primary rays, rtgi_gbuffer.comp): a single-sided triangle seen from behind does
// not stop a ray either, as the raster culls it; the caller sets cullDirection to
// the ray's direction before it traces. Include after
// scene_shared.h and octree.glsl.
#ifndef VOXGI_RTGI_BVH_GLSL
#define VOXGI_RTGI_BVH_GLSL

#include "pathtrace_shared.h"
layout(std430, binding = kMaterialBinding) readonly buffer Materials { GpuMaterial materials[]; };
layout(binding = kRtgiBvhNodeUnit) uniform usamplerBuffer nodeTexels;
layout(binding = kRtgiBvhTriangleUnit) uniform usamplerBuffer triangleTexels;
layout(binding = kRtgiBvhVertexUnit) uniform samplerBuffer sceneVertexTexels;
layout(std430, binding = kRtgiBvhIndexBinding) readonly buffer SceneIndices {
  uint sceneIndices[];
};
uint loopBudget;  // see kPtLoopBudget
const float kInf = 1.0 / 0.0;

#ifdef RTGI_BVH_TEXTURES
layout(std430, binding = kRtgiBvhTextureBinding) readonly buffer Textures { uvec4 textures[]; };
layout(binding = kRtgiBvhTexelUnit) uniform usamplerBuffer textureTexels;
#define VOXGI_BVH_UVS
#endif
#ifdef RTGI_BVH_COLORS
#define VOXGI_BVH_COLORS
#define VOXGI_BVH_COLOR_BINDING kRtgiBvhColorBinding
#endif
#ifdef RTGI_BVH_TANGENTS
#define VOXGI_BVH_TANGENTS
#define VOXGI_BVH_TANGENT_BINDING kRtgiBvhTangentBinding
#endif
#if defined(RTGI_BVH_ALPHA) || defined(RTGI_BVH_CULL)
#define VOXGI_BVH_ALPHA
#endif
#include "bvh_trace.glsl"

#if defined(RTGI_BVH_TEXTURES) || defined(RTGI_BVH_ALPHA)
// The path tracer's texture reads (texture_shared.h).
#define VOXGI_TABLES_PARAM
#define VOXGI_TABLES_ARG
#ifdef RTGI_BVH_TEXTURES
#define VOXGI_TEXEL(i) texelFetch(textureTexels, int(i)).x
#define VOXGI_TEXTURE(i) textures[i]
#else
#define VOXGI_TEXEL(i) 0u
#endif
#include "texture_shared.h"
#endif

#ifdef RTGI_BVH_CULL
vec3 cullDirection;  // the ray's direction, set before each trace
#endif

#if defined(RTGI_BVH_ALPHA) || defined(RTGI_BVH_CULL)
bool bvhHitStops(uint tri, vec2 bc) {
  GpuMaterial m = materials[triangleMaterial(tri)];
#ifdef RTGI_BVH_CULL
  if ((m.flags & kMaterialDoubleSided) == 0u) {
    GpuPtTriangle T = loadTriangle(tri);
    if (!(dot(cross(T.e1.xyz, T.e2.xyz), cullDirection) < 0.0)) return false;
  }
#endif
#ifndef RTGI_BVH_ALPHA
  return true;
#else
#ifdef RTGI_BVH_COLORS
  m.baseColor *= triangleColor(tri, bc);
#endif
#ifdef RTGI_BVH_TEXTURES
  uvec4 t = (m.flags & kMaterialHasTexture) != 0u ? textures[m.texture] : uvec4(0u);
  return alphaStops(m, true, t, triangleUv(tri, bc), alphaHash(tri, bc));
#else
  return alphaStops(m, false, uvec4(0u), vec2(0.0), alphaHash(tri, bc));
#endif
#endif
}
#endif

// The material where a ray met triangle tri at barycentrics bc, with its textures
// and vertex colour, as the path tracer reads it.
GpuMaterial hitMaterial(uint tri, vec2 bc) {
  GpuMaterial m = materials[triangleMaterial(tri)];
#ifdef RTGI_BVH_TEXTURES
  if ((m.flags & (kMaterialHasTexture | kMaterialHasEmissiveTexture |
                  kMaterialHasMetallicRoughnessTexture)) != 0u)
    m = texturedMaterial(
        m, triangleUv(tri, bc),
        (m.flags & kMaterialAnyUv2) != 0u ? triangleUv2(tri, bc) : triangleUv(tri, bc));
#endif
#ifdef RTGI_BVH_COLORS
  m.baseColor *= triangleColor(tri, bc);
#endif
  return m;
}

// Its base colour: what a leaf's albedo averages over the surfaces in its voxel.
vec3 hitBaseColor(uint tri, vec2 bc) { return hitMaterial(tri, bc).baseColor.rgb; }

// Ray offset off a triangle: a thousandth of a voxel, scaled with the scene.
float bvhEpsilon() { return 1e-3 * octreeVoxelSize(); }

// 1 if nothing lies between p and the point `dist` away along unit l. `toEmitter`:
// that point was drawn on an emitter, which must not shadow itself: the ray ends a
// thousandth of its length short of it, and `slack` more (a point on a cluster's
// disk lies up to the disk's radius behind its facets). An any-hit ray: it stops at
// the first occluder found, and never enters the emitter's own triangles (a lamp
// of thousands).
float bvhVisible(vec3 p, vec3 l, float dist, bool toEmitter, float slack) {
#ifdef VOXGI_NO_SHADOWS
  return 1.0;
#else
  loopBudget = kPtLoopBudget;
  float d = min(dist, 3.0e38);
  float tMax = toEmitter ? d * (1.0 - 1e-3) - slack : d * (1.0 - 1e-4);
  if (!(tMax > 0.0)) return 1.0;
  return occluded(p, l, tMax) ? 0.0 : 1.0;
#endif
}

#endif  // VOXGI_RTGI_BVH_GLSL
