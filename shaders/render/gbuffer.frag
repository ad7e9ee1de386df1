#version 450 core
// rtgi primary visibility: the G-buffer (see rtgi_shared.h for the layout).
// Effect-plan variants: VOXGI_NO_TEXTURES, VOXGI_NO_ALPHA, VOXGI_NO_EMISSION,
// VOXGI_NO_COLORS, VOXGI_NO_NORMALMAPS; VOXGI_NO_UV2 (no texture-coordinate channel 1).
#include "scene_shared.h"
#include "normal_map_shared.h"  // outside #if: its #line markers must stay
#include "sampling_shared.h"

layout(std140, binding = kFrameBinding) uniform FrameBlock { GpuFrame frame; };
layout(std430, binding = kMaterialBinding) readonly buffer Materials { GpuMaterial materials[]; };

layout(location = kMaterialIndexLocation) uniform int materialIndex;
layout(binding = kBaseColorUnit) uniform sampler2D baseColorTexture;
layout(binding = kEmissiveUnit) uniform sampler2D emissiveTexture;
layout(binding = kMetallicRoughnessUnit) uniform sampler2D metallicRoughnessTexture;

layout(location = 0) in vec3 vPosition;
layout(location = 1) in vec3 vNormal;
layout(location = 2) in vec2 vUv;  // texture-coordinate channel 0
#ifdef VOXGI_UV2
layout(location = 6) in vec2 vUv2;  // channel 1, for the slots whose kMaterial*Uv2 bit is set
// The texture coordinates of m's slot whose channel-1 bit is `bit` (kMaterial*Uv2).
#define SLOT_UV(m, bit) (((m).flags & (bit)) != 0u ? vUv2 : vUv)
#else
#define SLOT_UV(m, bit) vUv
#endif
#ifndef VOXGI_NO_COLORS
layout(location = 3) in vec4 vColor;
#endif
layout(location = 4) in vec3 vPreviousPosition;
#ifndef VOXGI_NO_NORMALMAPS
layout(binding = kNormalUnit) uniform sampler2D normalTexture;
layout(location = 5) in vec4 vTangent;
#endif

layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outAlbedo;
layout(location = 3) out vec4 outEmission;
layout(location = 4) out vec4 outMotion;  // where the point was last frame, less where it is

void main() {
  GpuMaterial m = materials[materialIndex];
  vec4 base = m.baseColor;
#ifndef VOXGI_NO_TEXTURES
  if ((m.flags & kMaterialHasTexture) != 0u) base *= texture(baseColorTexture, vUv);
#endif
#ifndef VOXGI_NO_COLORS
  base *= 1.0 + vColor;  // COLOR_0 (as its offset from white); white where the scene has none
#endif
#ifndef VOXGI_NO_ALPHA
  if ((m.flags & kMaterialAlphaMask) != 0u && base.a < m.alphaCutoff) discard;
  // Blended: the fragment is kept with probability alpha (scene_shared.h).
  if ((m.flags & kMaterialAlphaBlend) != 0u && !(base.a > pointHash01(vPosition))) discard;
#endif
  float metallic = m.metallic;
  float roughness = m.roughness;
  vec3 emission = m.emission;
#ifndef VOXGI_NO_TEXTURES
  // glTF: metallic in blue, roughness in green (a linear texture); emission sRGB.
  // The textures that shading depends on non-linearly (metallic-roughness, normal
  // map) are read at their finest level, as the path tracer reads them: rtgi
  // averages its jittered samples over the pixel, so it averages the lighting of
  // each texel, where a mip level would average the parameters first (a coarse
  // mip's mean roughness and flattened normals give another highlight: on the
  // lights_punctual_lamp sample at 160x160 the brass read 1.58x the path tracer's
  // light with mips, 1.17x without). Base colour and emission, which the light
  // scales linearly, keep their mipmaps.
  if ((m.flags & kMaterialHasMetallicRoughnessTexture) != 0u) {
    vec4 mr = textureLod(metallicRoughnessTexture, SLOT_UV(m, kMaterialMetallicRoughnessUv2), 0.0);
    metallic *= mr.b;
    roughness *= mr.g;
  }
  if ((m.flags & kMaterialHasEmissiveTexture) != 0u)
    emission *= texture(emissiveTexture, SLOT_UV(m, kMaterialEmissiveUv2)).rgb;
#endif
  vec3 n = normalize(vNormal);
  if (!(dot(n, n) > 0.5)) n = vec3(0.0, 1.0, 0.0);  // a degenerate normal: any unit vector
  // Two-sided surfaces are shaded on the side the viewer sees.
  if ((m.flags & kMaterialDoubleSided) != 0u && !gl_FrontFacing) n = -n;
#ifndef VOXGI_NO_NORMALMAPS
  // The shading normal the G-buffer stores: the normal map's, bent back towards the
  // viewer where it faces away (the back-facing rule of normal_map_shared.h).
  float packedSurfaceNormal = 0.0;  // none: the shading normal is the surface's
  if ((m.flags & kMaterialHasNormalTexture) != 0u) {
    packedSurfaceNormal = packSurfaceNormal(n);  // for rtgi's leak rule
    vec4 tangent = vTangent;
    if ((m.flags & kMaterialDoubleSided) != 0u && !gl_FrontFacing) tangent.w = -tangent.w;
    vec2 normalUv = SLOT_UV(m, kMaterialNormalUv2);
    n = perturbNormal(n, tangent, textureLod(normalTexture, normalUv, 0.0).rgb, m.normalScale);
    n = bendShadingNormal(n, normalize(frame.cameraPosition.xyz - vPosition));
  }
#endif
  outPosition = vec4(vPosition, 1.0 + float(materialIndex));
  outMotion = vec4(vPreviousPosition - vPosition, 0.0);
  outNormal = vec4(n, roughness);
  outAlbedo = vec4(clamp(base.rgb, 0.0, 1.0), clamp(metallic, 0.0, 1.0));
#ifdef VOXGI_NO_EMISSION
  outEmission = vec4(0.0);
#else
  outEmission = vec4(emission, 0.0);
#endif
#ifndef VOXGI_NO_NORMALMAPS
  outEmission.w = packedSurfaceNormal;
#endif
}
