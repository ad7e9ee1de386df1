// The path tracer's light sampling and texture reads, written once for GLSL and
// C++ (see shared_fn.h): shaders/render/pathtrace.comp (the GL device) and
// src/render/pathtrace_cpu.cpp (the CPU device) include this file, so both devices
// pick the same emitters with the same pdfs, weigh them with the same MIS weights
// and read the same texels. Each device brings its own ray casting and its own
// access to the tables through macros: the shader defines them before the include,
// C++ gets them below.
//   VOXGI_EMISSIVE(i)  the i-th GpuPtEmissive of the alias table;
//   VOXGI_TEXEL(i)     the i-th packed sRGB RGBA8 texel of all base-colour textures;
//   VOXGI_TABLES_PARAM / VOXGI_TABLES_ARG  how the tables reach a function (C++: a
//                      PtTables reference; GLSL: nothing, they are buffers).
// Twin test: tests/render/shading_twin_gltest.cpp.
#ifndef VOXGI_PATHTRACE_SHADING_H
#define VOXGI_PATHTRACE_SHADING_H

#include "brdf_shared.h"
#include "pathtrace_shared.h"
#include "scene_shared.h"

#ifdef __cplusplus
namespace voxgi::gpu {
using glm::isinf;
using glm::isnan;
using glm::smoothstep;
// The CPU device's tables.
struct PtTables {
  const GpuPtEmissive* emissive = nullptr;
  const uint* texels = nullptr;
};
#define VOXGI_TABLES_PARAM const PtTables &tables,
#define VOXGI_TABLES_ARG tables,
#define VOXGI_EMISSIVE(i) tables.emissive[i]
#define VOXGI_TEXEL(i) tables.texels[i]
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
// (Vose's construction, built in src/render/pathtrace_emitters.cpp) from one
// uniform number, then a uniform point on it from two more, as seen from p.
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
  vec3 q = vec3(e.v0) + vec3(e.e1) * (sq * (1.0f - u2)) + vec3(e.e2) * (sq * u2);
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

// --- base-colour textures -----------------------------------------------------------
// One decoded (linear) texel of texture t = (first texel, width, height, -).
VOXGI_FN vec4 srgbTexel(VOXGI_TABLES_PARAM uvec4 t, ivec2 p) {
  vec4 c = unpackUnorm4x8(VOXGI_TEXEL(t.x + uint(p.y) * t.y + uint(p.x)));
  vec3 rgb = vec3(c);
  vec3 lo = rgb / 12.92f;
  vec3 hi = pow((rgb + 0.055f) / 1.055f, vec3(2.4f));
  return vec4(c.r <= 0.04045f ? lo.r : hi.r, c.g <= 0.04045f ? lo.g : hi.g,
              c.b <= 0.04045f ? lo.b : hi.b, c.a);
}

// Texture t at uv, bilinear over linear (decoded) texels, repeating as the raster
// sampler does. No mipmaps: paths jittered over the pixel average the footprint.
VOXGI_FN vec4 sampleTexture(VOXGI_TABLES_PARAM uvec4 t, vec2 uv) {
  ivec2 size = ivec2(int(t.y), int(t.z));
  if (isnan(uv.x) || isinf(uv.x)) uv.x = 0.0f;
  if (isnan(uv.y) || isinf(uv.y)) uv.y = 0.0f;
  vec2 x = fract(uv) * vec2(size) - 0.5f;  // in [-0.5, size - 0.5)
  vec2 f = x - floor(x);
  ivec2 i0 = ivec2(floor(x));  // -1 .. size - 1
  ivec2 a = ivec2(i0.x < 0 ? i0.x + size.x : i0.x, i0.y < 0 ? i0.y + size.y : i0.y);
  ivec2 b = ivec2(a.x + 1 >= size.x ? 0 : a.x + 1, a.y + 1 >= size.y ? 0 : a.y + 1);
  return mix(
      mix(srgbTexel(VOXGI_TABLES_ARG t, a), srgbTexel(VOXGI_TABLES_ARG t, ivec2(b.x, a.y)), f.x),
      mix(srgbTexel(VOXGI_TABLES_ARG t, ivec2(a.x, b.y)), srgbTexel(VOXGI_TABLES_ARG t, b), f.x),
      f.y);
}

// --- alpha masks ------------------------------------------------------------------------
// Whether a ray stops at a hit at uv on material m: an alpha-masked material (glTF
// MASK) lets rays through where base alpha x texture alpha < its cutoff, as the
// raster modes discard those fragments. `texture` is m's table entry (read only
// when `textured` and m has a texture).
VOXGI_FN bool alphaStops(VOXGI_TABLES_PARAM GpuMaterial m, bool textured, uvec4 texture, vec2 uv) {
  if ((m.flags & kMaterialAlphaMask) == 0u) return true;
  float a = m.baseColor.a;
  if (textured && (m.flags & kMaterialHasTexture) != 0u)
    a *= sampleTexture(VOXGI_TABLES_ARG texture, uv).a;
  return a >= m.params.z;
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_PATHTRACE_SHADING_H
