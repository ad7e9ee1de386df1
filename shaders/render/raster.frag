#version 450 core
// Raster baseline: emission plus unshadowed direct light from punctual lights and
// emissive surfaces, and an optional uniform ambient term that the material's
// occlusion texture darkens (glTF occlusionTexture), in linear HDR radiance. Effect-plan variants
// (scene/effects.h): VOXGI_NO_TEXTURES, VOXGI_NO_ALPHA, VOXGI_NO_EMISSION, VOXGI_NO_COLORS,
// VOXGI_NO_NORMALMAPS compile that code out; VOXGI_NO_UV2 texture-coordinate channel 1
// (every slot then reads channel 0, the only one the scene has).
#include "scene_shared.h"
#include "normal_map_shared.h"  // outside #if: its #line markers must stay
#include "lighting.glsl"
#include "sampling_shared.h"

layout(std140, binding = kFrameBinding) uniform FrameBlock { GpuFrame frame; };
layout(std430, binding = kMaterialBinding) readonly buffer Materials { GpuMaterial materials[]; };
layout(std430, binding = kLightBinding) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = kEmitterBinding) readonly buffer Emitters { GpuEmitter emitters[]; };

layout(location = kMaterialIndexLocation) uniform int materialIndex;
layout(binding = kBaseColorUnit) uniform sampler2D baseColorTexture;
layout(binding = kEmissiveUnit) uniform sampler2D emissiveTexture;
layout(binding = kMetallicRoughnessUnit) uniform sampler2D metallicRoughnessTexture;
layout(binding = kOcclusionUnit) uniform sampler2D occlusionTexture;
// Uniform ambient radiance (grey): no light of the scene, the stand-in for the
// indirect light the baseline does not compute (RenderSettings::ambient; 0: none).
layout(location = kAmbientLocation) uniform float ambient;

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
#ifndef VOXGI_NO_NORMALMAPS
layout(binding = kNormalUnit) uniform sampler2D normalTexture;
layout(location = 5) in vec4 vTangent;
#endif

layout(location = 0) out vec4 outRadiance;

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
  if ((m.flags & kMaterialHasMetallicRoughnessTexture) != 0u) {
    vec4 mr = texture(metallicRoughnessTexture, SLOT_UV(m, kMaterialMetallicRoughnessUv2));
    metallic *= mr.b;
    roughness *= mr.g;
  }
  if ((m.flags & kMaterialHasEmissiveTexture) != 0u)
    emission *= texture(emissiveTexture, SLOT_UV(m, kMaterialEmissiveUv2)).rgb;
#endif

  Surface s;
  s.p = vPosition;
  s.v = normalize(frame.cameraPosition.xyz - vPosition);
  s.n = normalize(vNormal);
  // Two-sided surfaces are lit on the side the viewer sees.
  if ((m.flags & kMaterialDoubleSided) != 0u && !gl_FrontFacing) s.n = -s.n;
#ifndef VOXGI_NO_NORMALMAPS
  // The vertex normal stays the surface's side: lights below it do not reach the
  // point whatever the mapped normal says (no light leaks; normal_map_shared.h).
  vec3 surfaceNormal = s.n;
  bool mapped = (m.flags & kMaterialHasNormalTexture) != 0u;
  if (mapped) {
    vec4 tangent = vTangent;
    if ((m.flags & kMaterialDoubleSided) != 0u && !gl_FrontFacing) tangent.w = -tangent.w;
    vec2 normalUv = SLOT_UV(m, kMaterialNormalUv2);
    s.n = perturbNormal(s.n, tangent, texture(normalTexture, normalUv).rgb, m.normalScale);
    s.n = bendShadingNormal(s.n, s.v);  // the back-facing rule
  }
#endif
  s.diffuse = base.rgb * (1.0 - metallic);
  s.f0 = metallicF0(base.rgb, metallic);
  s.alpha = roughness * roughness;
  s.specular = isLambertian(metallic, roughness) ? 0.0 : 1.0;

#ifdef VOXGI_NO_EMISSION
  vec3 radiance = vec3(0.0);
#else
  vec3 radiance = emission;
#endif
  // The ambient term, darkened by the occlusion texture (red channel) mixed in by
  // its strength: occlusion scales indirect light only, as glTF defines it.
  float occlusion = 1.0;
#ifndef VOXGI_NO_TEXTURES
  if ((m.flags & kMaterialHasOcclusionTexture) != 0u)
    occlusion = mix(1.0, texture(occlusionTexture, SLOT_UV(m, kMaterialOcclusionUv2)).r,
                    m.occlusionStrength);
#endif
  radiance += ambient * occlusion * s.diffuse;
  int lightCount = int(frame.counts.x);
#ifndef VOXGI_NO_NORMALMAPS
  for (int i = 0; i < lightCount; ++i) {
    if (mapped) {
      GpuLight light = lights[i];
      vec3 l = uint(light.positionType.w) == kLightDirectional ? -light.directionRange.xyz
                                                               : light.positionType.xyz - s.p;
      if (dot(l, surfaceNormal) <= 0.0) continue;
    }
    radiance += punctualLight(lights[i], s);
  }
#else
  for (int i = 0; i < lightCount; ++i) radiance += punctualLight(lights[i], s);
#endif
#ifndef VOXGI_NO_EMISSION
  int emitterCount = int(frame.counts.y);
  for (int i = 0; i < emitterCount; ++i) radiance += areaLight(emitters[i], s);
#endif
  outRadiance = vec4(radiance, 1.0);
}
