// The path tracer's light sampling, written once for GLSL and C++ (see
// shared_fn.h); with texture_shared.h (texture reads, alpha masks) it is what
// shaders/render/pathtrace.comp (the GL device) and src/render/pathtrace/pathtrace_cpu.cpp
// (the CPU device) share, so both devices pick the same emitters with the same
// pdfs, weigh them with the same MIS weights and read the same texels. The tables
// reach these functions through the macros of texture_shared.h.
// Twin test: tests/render/shading_twin_gltest.cpp.
#ifndef VOXGI_PATHTRACE_SHADING_H
#define VOXGI_PATHTRACE_SHADING_H

#include "brdf_shared.h"
#include "pathtrace_shared.h"
#include "scene_shared.h"
#include "texture_shared.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// --- emissive triangles (next-event estimation) ----------------------------------------
// A point on one emissive triangle, seen from the shading point.
struct EmitterSample {
  vec3 wi;         // unit direction towards the point
  float dist;      // distance to it
  float pdfLight;  // solid-angle pdf of having sampled this direction (0: no sample)
  vec3 radiance;   // what the point emits towards the shading point
};

// Picks one of `count` emissive triangles by power through the Walker alias table
// (Vose's construction, built in src/render/pathtrace/pathtrace_scene.cpp) from one
// uniform number, then a uniform point on it from two more, as seen from p. An
// emissive texture is read at that point where the device reads textures
// (VOXGI_TEXTURE defined).
VOXGI_FN EmitterSample sampleEmitter(VOXGI_TABLES_PARAM vec3 p, uint count, float u0, float u1,
                                     float u2) {
  EmitterSample s;
  s.pdfLight = 0.0f;
  s.wi = vec3(0.0f);
  s.dist = 0.0f;
  s.radiance = vec3(0.0f);
  float u = u0 * float(count);
  uint i = min(uint(u), count - 1u);
  GpuPtEmissive e = VOXGI_EMISSIVE(i);
  if (u - float(i) >= e.v0.w) e = VOXGI_EMISSIVE(floatBitsToUint(e.e1.w));
  float sq = sqrt(u1);
  float b1 = sq * (1.0f - u2);
  float b2 = sq * u2;
  vec3 q = vec3(e.v0) + vec3(e.e1) * b1 + vec3(e.e2) * b2;
  vec3 c = cross(vec3(e.e1), vec3(e.e2));
  float area2 = length(c);
  vec3 nl = c / area2;
  vec3 toL = q - p;
  float dist2 = dot(toL, toL);
  float dist = sqrt(dist2);
  vec3 wi = toL / dist;
  float cosL = -dot(nl, wi);
  if (e.radiance.w > 0.5f) cosL = abs(cosL);
  if (cosL <= 0.0f || !(dist > 0.0f)) return s;
  s.wi = wi;
  s.dist = dist;
  s.pdfLight = e.e2.w / (0.5f * area2) * dist2 / cosL;
  s.radiance = vec3(e.radiance);
#ifdef VOXGI_TEXTURE
  uint texture = floatBitsToUint(e.uv2.z);
  if (texture != 0u) {  // the emissive texture at the point (the same uniform map)
    vec2 uv = vec2(e.uv01.x, e.uv01.y) * (1.0f - b1 - b2) + vec2(e.uv01.z, e.uv01.w) * b1 +
              vec2(e.uv2.x, e.uv2.y) * b2;
    s.radiance *= vec3(sampleTexture(VOXGI_TABLES_ARG VOXGI_TEXTURE(texture - 1u), uv));
  }
#endif
  return s;
}

// MIS weight of emission found by BSDF sampling (pdf bsdfPdf) on a triangle that
// next-event estimation picks with area density areaPdf, at distance t and cosine
// cosL from the ray.
VOXGI_FN float emissionMisWeight(float bsdfPdf, float areaPdf, float t, float cosL) {
  float pdfLight = areaPdf * t * t / max(cosL, 1e-20f);
  return powerHeuristic(bsdfPdf, pdfLight);
}

// --- punctual lights (KHR_lights_punctual; delta lights, NEE only) ---------------------
struct PunctualSample {
  vec3 wi;        // unit direction towards the light
  float dist;     // distance to it (1e30 for directional lights)
  vec3 radiance;  // incident radiance x attenuation (0: no light here)
};

VOXGI_FN PunctualSample samplePunctual(GpuLight light, vec3 p) {
  PunctualSample s;
  uint type = uint(light.positionType.w);
  float atten = 1.0f;
  s.dist = 1e30f;
  if (type == kLightDirectional) {
    s.wi = -normalize(vec3(light.directionRange));
  } else {
    vec3 d = vec3(light.positionType) - p;
    float dist2 = max(dot(d, d), 1e-30f);
    s.dist = sqrt(dist2);
    s.wi = d / s.dist;
    atten = 1.0f / dist2;
    float range = light.directionRange.w;
    if (range > 0.0f) {  // the glTF spec's recommended smooth window, as in raster
      float x = s.dist / range;
      atten *= clamp(1.0f - x * x * x * x, 0.0f, 1.0f);
    }
    if (type == kLightSpot) {
      float cd = dot(normalize(vec3(light.directionRange)), -s.wi);
      atten *= smoothstep(light.cone.y, light.cone.x, cd);
    }
  }
  s.radiance = vec3(light.radiance) * atten;
  return s;
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_PATHTRACE_SHADING_H
