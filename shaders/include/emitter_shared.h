// The irradiance a receiver gets from one emitter per unit of emitted radiance, in
// the common subset of GLSL and C++ (shared_fn.h): the one source of lighting.glsl's
// emitterFactor() and of scene::emitterIrradianceFactor, which the C++ tests hold to
// closed forms. A triangle: Lambert's formula for a polygon, the triangle clipped to
// the receiver's upper hemisphere. A cluster of far emitters (the light tree's
// inner nodes): a disc of the cluster's area facing along its mean normal.
#ifndef VOXGI_EMITTER_SHARED_H
#define VOXGI_EMITTER_SHARED_H

#include "shared_fn.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// One edge's term of Lambert's formula for the irradiance of a polygon of unit
// radiance: theta (gamma . n), for the edge from pa to pb (relative to the receiver).
VOXGI_FN float lambertEdge(vec3 pa, vec3 pb, vec3 n) {
  float la = length(pa);
  float lb = length(pb);
  if (!(la > 1e-30f) || !(lb > 1e-30f)) return 0.0f;  // a corner at the receiver itself
  vec3 a = pa / la;
  vec3 b = pb / lb;
  vec3 c = cross(a, b);
  float s = length(c);
  if (!(s >= 1e-12f)) return 0.0f;
  return atan(s, dot(a, b)) * dot(c / s, n);
}

// The term of edge a -> b (heights da, db above the tangent plane) clipped to the
// upper hemisphere, without branches: an end below the plane moves to where the
// edge crosses it. Records that crossing as the polygon's exit (a above, b below)
// or entry (a below, b above) point on the plane.
VOXGI_FN float lambertClippedEdge(vec3 a, vec3 b, float da, float db, vec3 n,
                                  VOXGI_INOUT(vec3) exitPoint, VOXGI_INOUT(vec3) entryPoint) {
  vec3 x = a + (b - a) * (da / (da - db));  // used only when the signs differ
  bool aboveA = da > 0.0f, aboveB = db > 0.0f;
  exitPoint = aboveA && !aboveB ? x : exitPoint;
  entryPoint = !aboveA && aboveB ? x : entryPoint;
  float term = lambertEdge(aboveA ? a : x, aboveB ? b : x, n);
  return aboveA || aboveB ? term : 0.0f;
}

// Irradiance per unit radiance at p (normal n) from the triangle v0 v1 v2, which
// emits on the side its winding faces, or on both.
VOXGI_FN float triangleEmitterFactor(vec3 v0, vec3 v1, vec3 v2, bool twoSided, vec3 p, vec3 n) {
  vec3 en = normalize(cross(v1 - v0, v2 - v0));
  if (!twoSided && dot(en, p - v0) <= 0.0f) return 0.0f;
  // The triangle clipped to the receiver's upper hemisphere: each edge keeps its
  // part above the tangent plane, and where the triangle dips below, the clipped
  // polygon closes along the plane from the exit point to the entry point. Written
  // without arrays or loops (a dynamically indexed local array is slow on a SIMD
  // software rasterizer).
  vec3 a = v0 - p, b = v1 - p, c = v2 - p;
  float da = dot(a, n), db = dot(b, n), dc = dot(c, n);
  if (da <= 0.0f && db <= 0.0f && dc <= 0.0f) return 0.0f;
  vec3 exitPoint = vec3(0.0f), entryPoint = vec3(0.0f);
  float sum = lambertClippedEdge(a, b, da, db, n, exitPoint, entryPoint) +
              lambertClippedEdge(b, c, db, dc, n, exitPoint, entryPoint) +
              lambertClippedEdge(c, a, dc, da, n, exitPoint, entryPoint);
  if (da <= 0.0f || db <= 0.0f || dc <= 0.0f) sum += lambertEdge(exitPoint, entryPoint, n);
  return 0.5f * abs(sum);
}

// Irradiance per unit radiance at p (normal n) from a cluster of emitters of total
// `area` around `center`, facing along `normal` (or both ways): a disc's, d^2 + A/pi
// keeping it finite at the centre.
VOXGI_FN float clusterEmitterFactor(vec3 center, vec3 normal, float area, bool twoSided, vec3 p,
                                    vec3 n) {
  vec3 toC = center - p;
  float d2 = dot(toC, toC);
  vec3 w = toC * inversesqrt(max(d2, 1e-30f));
  float cosE = -dot(normal, w);
  if (twoSided) cosE = abs(cosE);
  float cosR = dot(n, w);
  if (cosE <= 0.0f || cosR <= 0.0f) return 0.0f;
  return area * cosE * cosR / (d2 + area / kPi);
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_EMITTER_SHARED_H
