#version 450 core
// rtgi stage "shadows": direct light at each pixel's surface with one shadow ray per
// light through the octree. Punctual lights: their exact contribution x visibility.
// Emissive surfaces, when there are few: their summed unshadowed contribution
// (exact irradiance, GGX highlight) x the visibility of one random point on one of
// them, drawn in proportion to its contribution (one shadow ray per pixel); with
// many, one emitter drawn by power per pixel and frame (light importance
// sampling), its contribution x visibility divided by its probability. Accumulation over frames turns the visibility samples into soft
// shadows. Mirrors take no highlight here: their reflected ray sees the light.
// Effect-plan variants (scene/effects.h): VOXGI_NO_SHADOWS traces no shadow ray (the
// renderer then names the stage "direct"); VOXGI_NO_EMISSION leaves emitters out.
// Scene variants (RtgiPass): RTGI_LIGHTS when there are punctual lights,
// RTGI_EMITTERS_EXACT (few emitters) or RTGI_EMITTERS_SAMPLED (many) when there are
// emitters. A software rasterizer runs both sides of every branch under a lane
// mask, and a loop's body at least once: code for what the scene lacks would cost
// as much as code that runs, so it is compiled out.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "octree_light.glsl"
#define RTGI_PIXEL_LIST
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiTraceGroup) in;

layout(binding = kDirectImage, rgba16f) uniform writeonly image2D directOut;

float lightVisible(vec3 o, vec3 l, float dist) {
#ifdef VOXGI_NO_SHADOWS
  return 1.0;
#else
  return octreeVisible(o, l, dist, 0.0, 0.0);
#endif
}

void main() {
  ivec2 px;
  if (!tracePixel(px)) return;
  Pixel p = loadPixel(px);
  vec3 result = vec3(0.0);
  if (p.covered) {
    seedPixel(px, 1u);
    Surface s = p.s;
    if (p.roughness < kMirrorRoughness) s.f0 = vec3(0.0);
    vec3 o = surfaceRayOrigin(px, s);
#ifdef RTGI_LIGHTS
    int lightCount = int(rtgi.counts.x);
    for (int k = 0; k < lightCount; ++k) {
      vec3 c = punctualLight(lights[k], s);
      if (all(equal(c, vec3(0.0)))) continue;
      vec3 l;
      float dist;
      punctualDirection(lights[k], s.p, l, dist);
      if (belowSurface(px, l)) continue;  // light under the surface (a normal map's leak)
      result += c * lightVisible(o, l, dist);
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
      // Few emitters: their exact unshadowed sum, times the visibility of one point
      // on one of them, drawn in proportion to its share of the sum.
      // One pass, no array: emitter k replaces the pick with probability
      // w_k / (w_0 + ... + w_k), which leaves each picked in proportion to w_k; the
      // one uniform number is rescaled after each decision, so it stays uniform.
      vec3 sum = vec3(0.0);
      float total = 0.0;
      float u = rand01();
      int pick = -1;
      for (int k = 0; k < emitterCount; ++k) {
        vec3 c = areaLight(emitters[k], s);
        float w = dot(c, vec3(0.2126, 0.7152, 0.0722));
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
      if (pick >= 0) result += sum * emitterVisible(emitters[pick], o, 0.0);
    }
#elif defined(RTGI_EMITTERS_SAMPLED)
    if (emitterCount > 0) {
      float pmf;
      GpuEmitter e = emitters[pickEmitter(rand01(), emitterCount, pmf)];
      vec3 c = areaLight(e, s);
      if (pmf > 0.0 && any(greaterThan(c, vec3(0.0))))
        result += c * emitterVisible(e, o, 0.0) / pmf;
    }
#endif
#endif
  }
  imageStore(directOut, px, vec4(result, 1.0));
}
