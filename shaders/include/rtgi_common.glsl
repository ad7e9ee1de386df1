// What the rtgi per-pixel stages share: parameters, the G-buffer, the surface at a
// pixel and its random stream. Include after scene_shared.h, lighting.glsl,
// sampling.glsl and octree.glsl.
#ifndef VOXGI_RTGI_COMMON_GLSL
#define VOXGI_RTGI_COMMON_GLSL

#include "rtgi_shared.h"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;
layout(std140, binding = kRtgiParamsBinding) uniform RtgiBlock { RtgiParams rtgi; };
layout(binding = kGPositionUnit) uniform sampler2D gPosition;
layout(binding = kGNormalUnit) uniform sampler2D gNormal;
layout(binding = kGAlbedoUnit) uniform sampler2D gAlbedo;
layout(binding = kGEmissionUnit) uniform sampler2D gEmission;

struct Pixel {
  bool covered;
  Surface s;
  float roughness;
  float metallic;
  vec3 base;
};

Pixel loadPixel(ivec2 px) {
  Pixel p;
  vec4 pos = texelFetch(gPosition, px, 0);
  vec4 nr = texelFetch(gNormal, px, 0);
  vec4 am = texelFetch(gAlbedo, px, 0);
  p.covered = pos.w > 0.5;
  p.roughness = clamp(nr.w, 0.0, 1.0);
  p.metallic = am.a;
  p.base = am.rgb;
  p.s.p = pos.xyz;
  p.s.n = normalize(nr.xyz);
  p.s.v = normalize(rtgi.camera.xyz - pos.xyz);
  p.s.diffuse = am.rgb * (1.0 - am.a);
  p.s.f0 = mix(vec3(0.04), am.rgb, am.a);
  p.s.alpha = p.roughness * p.roughness;
  return p;
}

// A stream per pixel, per frame and per stage: a hash of the pixel alone would
// repeat the same samples every frame, and accumulation would converge to a biased
// image.
void seedPixel(ivec2 px, uint stage) {
  uint pixelIndex = uint(px.y) * rtgi.frame.z + uint(px.x);
  rngState = pcgHash(pcgHash(pcgHash(rtgi.frame.y + stage * 0x9e3779b9u) + pixelIndex) +
                     rtgi.frame.x);
}

// Where rays leave the surface: off it along the normal (see kSurfaceOffsetVoxels).
vec3 rayOrigin(Surface s) { return s.p + s.n * (kSurfaceOffsetVoxels * octreeVoxelSize()); }

bool outside(ivec2 px) { return px.x >= int(rtgi.frame.z) || px.y >= int(rtgi.frame.w); }

#endif  // VOXGI_RTGI_COMMON_GLSL
