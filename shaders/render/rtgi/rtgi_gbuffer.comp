#version 450 core
// rtgi primary visibility by rays (RtgiPass::Settings::Primary::kRays): the G-buffer
// gbuffer.frag writes, made by one closest-hit ray a pixel through the scene's BVH
// instead of by rasterizing every triangle. A rasterizer's cost grows with the
// triangles it draws, a ray's with their logarithm: on a software GL, a scene of
// millions of triangles spends most of its frame in the raster G-buffer
// (docs/scale.md). Each ray leaves the camera through the pixel's jittered centre
// (the frame's view-projection, jitter included), starts at the camera (the raster
// clips what lies nearer than its near plane, 1e-5 of the far one) and skips single-sided triangles
// seen from behind (which the raster culls; RTGI_BVH_CULL). The surface is read as at an indirect
// hit (rtgi_hit.glsl): textures at their finest level, as the path tracer reads them, where the
// raster reads base colour and emission through mipmaps; the jittered samples of accumulation
// average the texels over the pixel alike. Meshes that move have no BVH, so the motion written is
// 0. Variants: the BVH's (RtgiPass::bvhDefines) and the effect plan's (VOXGI_NO_*).
#include "scene_shared.h"
#include "normal_map_shared.h"  // outside #if: its #line markers must stay
#include "octree.glsl"
#define RTGI_BVH_CULL
#include "rtgi_bvh.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, binding = kFrameBinding) uniform FrameBlock { GpuFrame frame; };
layout(binding = kGbufferPositionImage, rgba32f) uniform writeonly image2D outPosition;
layout(binding = kGbufferNormalImage, rgba16f) uniform writeonly image2D outNormal;
layout(binding = kGbufferAlbedoImage, rgba8) uniform writeonly image2D outAlbedo;
layout(binding = kGbufferEmissionImage, rgba16f) uniform writeonly image2D outEmission;
layout(binding = kGbufferMotionImage, rgba16f) uniform writeonly image2D outMotion;

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(outPosition);
  if (any(greaterThanEqual(px, size))) return;
  mat4 viewProj = mat4(frame.viewProj[0], frame.viewProj[1], frame.viewProj[2], frame.viewProj[3]);
  // Towards the pixel's centre on the far plane (reversed depth: z = 0 there), which
  // a float inverse finds far more precisely than the near plane's point, whose
  // distance from the camera may be 1e-5 of the scene's.
  vec2 ndc = (vec2(px) + 0.5) / vec2(size) * 2.0 - 1.0;
  vec4 far = inverse(viewProj) * vec4(ndc, 0.0, 1.0);
  vec3 o = frame.cameraPosition.xyz;
  vec3 dir = normalize(far.xyz / far.w - o);
  imageStore(outMotion, px, vec4(0.0));

  loopBudget = kPtLoopBudget;
  cullDirection = dir;
  float t;
  uint tri;
  vec2 bc;
  if (!(dir == dir) || !trace(o, dir, kInf, false, t, tri, bc)) {
    // Nothing: the background, as the raster's clear leaves it.
    imageStore(outPosition, px, vec4(0.0));
    imageStore(outNormal, px, vec4(0.0));
    imageStore(outAlbedo, px, vec4(0.0));
    imageStore(outEmission, px, vec4(0.0));
    return;
  }
  GpuPtTriangle T = loadTriangle(tri);
  uint materialIndex = floatBitsToUint(T.v0.w);
  GpuMaterial m = materials[materialIndex];
#ifdef RTGI_BVH_TEXTURES
  vec2 uv = triangleUv(tri, bc);
  vec2 uv2 = (m.flags & kMaterialAnyUv2) != 0u ? triangleUv2(tri, bc) : uv;
  GpuMaterial textured = texturedMaterial(m, uv, uv2);
#else
  GpuMaterial textured = m;
#endif
  vec4 base = textured.baseColor;
#ifdef RTGI_BVH_COLORS
  base *= triangleColor(tri, bc);
#endif
  vec3 p = T.v0.xyz + bc.x * T.e1.xyz + bc.y * T.e2.xyz;
  bool front = dot(cross(T.e1.xyz, T.e2.xyz), dir) < 0.0;
  // The interpolated normal, turned as gbuffer.frag turns it.
  vec3 n = normalize(triangleNormal(tri, bc));
  if (!(dot(n, n) > 0.5)) n = vec3(0.0, 1.0, 0.0);
  if ((m.flags & kMaterialDoubleSided) != 0u && !front) n = -n;
  float packedSurfaceNormal = 0.0;
#ifdef RTGI_BVH_TANGENTS
  if ((m.flags & kMaterialHasNormalTexture) != 0u) {
    packedSurfaceNormal = packSurfaceNormal(n);
    vec4 tangent = triangleTangent(tri, bc);
    if ((m.flags & kMaterialDoubleSided) != 0u && !front) tangent.w = -tangent.w;
    n = bendShadingNormal(mappedNormal(m, n, tangent, uv, uv2), -dir);
  }
#endif
  vec3 emission = textured.emission;
#ifdef VOXGI_NO_EMISSION
  emission = vec3(0.0);
#endif
  imageStore(outPosition, px, vec4(p, 1.0 + float(materialIndex)));
  imageStore(outNormal, px, vec4(n, textured.roughness));
  imageStore(outAlbedo, px, vec4(clamp(base.rgb, 0.0, 1.0), clamp(textured.metallic, 0.0, 1.0)));
  imageStore(outEmission, px, vec4(emission, packedSurfaceNormal));
}
