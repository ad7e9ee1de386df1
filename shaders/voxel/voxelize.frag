#version 450 core
// Voxelization, fragment stage. The framebuffer has no attachments and 4x MSAA,
// so a fragment runs for every pixel where any of its 4 samples is covered: a
// triangle thinner than a voxel still lands (the portable stand-in for conservative
// rasterization, which llvmpipe lacks). What a fragment adds: voxel_fragment.glsl.
// Effect-plan variants: VOXGI_NO_TEXTURES, VOXGI_NO_ALPHA, VOXGI_NO_EMISSION,
// VOXGI_NO_COLORS.
#include "scene_shared.h"
#include "voxel_shared.h"

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kMaterialBinding) readonly buffer Materials { GpuMaterial materials[]; };
layout(location = kMaterialIndexLocation) uniform int materialIndex;
layout(binding = kBaseColorUnit) uniform sampler2D baseColorTexture;
layout(binding = kEmissiveUnit) uniform sampler2D emissiveTexture;

#include "voxel_fragment.glsl"

layout(location = 0) centroid in vec3 gNormal;
layout(location = 1) centroid in vec2 gUv;
#if defined(VOXGI_UV2) && !defined(VOXGI_NO_EMISSION)
layout(location = 6) centroid in vec2 gUv2;  // channel 1 (kMaterialEmissiveUv2)
#endif
layout(location = 2) flat in int gAxis;
layout(location = 3) flat in vec4 gPlane;
layout(location = 4) flat in vec2 gDepth;
#ifndef VOXGI_NO_COLORS
layout(location = 5) centroid in vec4 gColor;
#endif

void main() {
  GpuMaterial m = materials[materialIndex];
  vec4 base = m.baseColor;
#ifndef VOXGI_NO_TEXTURES
  if ((m.flags & kMaterialHasTexture) != 0u) base *= texture(baseColorTexture, gUv);
#endif
#ifndef VOXGI_NO_COLORS
  base *= 1.0 + gColor;  // COLOR_0 (as its offset from white); white where the scene has none
#endif
#ifndef VOXGI_NO_ALPHA
  // Blended surfaces where they are at least half opaque (their cutoff: GpuScene).
  if ((m.flags & (kMaterialAlphaMask | kMaterialAlphaBlend)) != 0u && base.a < m.alphaCutoff)
    discard;
#endif

  uint weight = uint(bitCount(gl_SampleMaskIn[0]));
  if (weight == 0u) return;
  vec3 n = normalize(gNormal);
  if (any(isnan(n))) n = vec3(0.0);
#ifdef VOXGI_NO_EMISSION
  vec3 e = vec3(0.0);
#else
  vec3 e = m.emission * voxel.gridInfo.y;  // scaled so the scene's largest is 1
#ifndef VOXGI_NO_TEXTURES
  if ((m.flags & kMaterialHasEmissiveTexture) != 0u)
#ifdef VOXGI_UV2
    e *= texture(emissiveTexture, (m.flags & kMaterialEmissiveUv2) != 0u ? gUv2 : gUv).rgb;
#else
    e *= texture(emissiveTexture, gUv).rgb;
#endif
#endif
#endif
  voxelAddFragment(ivec2(gl_FragCoord.xy), gAxis, gPlane, gDepth, base.rgb, n, e, weight);
}
