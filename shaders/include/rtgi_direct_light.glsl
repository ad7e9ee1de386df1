// Direct light reflected at a surface towards its viewer, as rtgi estimates it at
// the pixels (rtgi_direct.comp) and at the hits of their reflected rays
// (rtgi_specular.comp). Punctual lights: their exact contribution x visibility.
// Emissive surfaces, when there are few (RTGI_EMITTERS_EXACT): their summed
// unshadowed contribution (exact irradiance, GGX highlight) x the visibility of one
// random point on one of them, drawn in proportion to its contribution (one shadow
// ray); with many (RTGI_EMITTERS_SAMPLED), one emitter drawn from the light tree
// (light_tree_shared.h) in proportion to a bound on its contribution at the point,
// its contribution x visibility divided by its probability (light importance
// sampling).
// Accumulation over frames turns the visibility samples into soft shadows.
// VOXGI_NO_SHADOWS: no shadow ray, and the exact sum over the emitters;
// VOXGI_NO_EMISSION: no emitters. RTGI_LIGHTS: the scene has punctual lights.
//
// The including shader defines the shadow ray first:
//   float shadowRay(vec3 o, vec3 l, float dist, bool toEmitter, float slack)
// 1 if the segment from o along unit l, dist long, is clear. toEmitter: it ends on a
// point drawn on an emitter, which must not shadow itself, and which may lie up to
// `slack` off the emitter's surface (emitterSlack).
#ifndef VOXGI_RTGI_DIRECT_LIGHT_GLSL
#define VOXGI_RTGI_DIRECT_LIGHT_GLSL

#ifdef RTGI_EMITTERS_SAMPLED
#include "light_tree_shared.h"
layout(std430, binding = kLightTreeBinding) readonly buffer LightTree { GpuLightNode lightTree[]; };
GpuLightNode lightTreeNode(int i) { return lightTree[i]; }
#endif

// How far off its surface a point drawn on emitter e may lie (emitterPoint): a
// cluster's points lie on its disk, up to its radius from the facets.
float emitterSlack(GpuEmitter e) {
  return uint(e.a.w) == kEmitterCluster ? sqrt(e.b.w / kPi) : 0.0;
}

// `ng`: the surface's own normal where a normal map tilts s.n, else 0: light from
// below it does not count (the leak rule, normal_map_shared.h).
vec3 directLight(Surface s, vec3 o, vec3 ng) {
  vec3 result = vec3(0.0);
#ifdef RTGI_LIGHTS
  int lightCount = int(rtgi.counts.x);
  for (int k = 0; k < lightCount; ++k) {
    vec3 c = punctualLight(lights[k], s);
    if (all(equal(c, vec3(0.0)))) continue;
    vec3 l;
    float dist;
    punctualDirection(lights[k], s.p, l, dist);
    if (dot(l, ng) < 0.0) continue;
    result += c * shadowRay(o, l, dist, false, 0.0);
  }
#endif
#ifndef VOXGI_NO_EMISSION
  int emitterCount = int(rtgi.counts.y);
#ifdef VOXGI_NO_SHADOWS
  // Unshadowed: the exact sum of every emitter's contribution.
  for (int k = 0; k < emitterCount; ++k) result += areaLight(emitters[k], s);
  emitterCount = 0;
#endif
#if defined(RTGI_EMITTERS_EXACT)
  {
    // One pass, no array: emitter k replaces the pick with probability
    // w_k / (w_0 + ... + w_k), which leaves each picked in proportion to w_k; the
    // one uniform number is rescaled after each decision, so it stays uniform.
    vec3 sum = vec3(0.0);
    float total = 0.0;
    float u = rand01();
    int pick = -1;
    for (int k = 0; k < emitterCount; ++k) {
      vec3 c = areaLight(emitters[k], s);
      float w = luminance(c);
      sum += c;
      if (!(w > 0.0)) continue;
      total += w;
      float q = w / total;
      if (u < q) {
        pick = k;
        u = u / q;
      } else {
        u = (u - q) / (1.0 - q);
      }
    }
    if (pick >= 0) {
      vec3 q = emitterPoint(emitters[pick], vec2(rand01(), rand01()));
      vec3 d = q - o;
      float dist = length(d);
      float slack = emitterSlack(emitters[pick]);
      if (dot(d, ng) >= 0.0)
        result += sum * (dist > 0.0 ? shadowRay(o, d / dist, dist, true, slack) : 1.0);
    }
  }
#elif defined(RTGI_EMITTERS_SAMPLED)
  if (emitterCount > 0) {
    float pmf;
    float u = rand01();
    int pick = pickLightTree(u, floatBitsToUint(rand01()), s.p, s.n, pmf);
    if (pick >= 0 && pmf > 0.0) {
      GpuEmitter e = emitters[pick];
      vec3 c = areaLight(e, s);
      if (any(greaterThan(c, vec3(0.0)))) {
        vec3 q = emitterPoint(e, vec2(rand01(), rand01()));
        vec3 d = q - o;
        float dist = length(d);
        if (dot(d, ng) >= 0.0)
          result +=
              c * (dist > 0.0 ? shadowRay(o, d / dist, dist, true, emitterSlack(e)) : 1.0) / pmf;
      }
    }
  }
#endif
#endif
  return result;
}

#endif  // VOXGI_RTGI_DIRECT_LIGHT_GLSL
