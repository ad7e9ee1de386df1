// Direct lighting without visibility: punctual lights (KHR_lights_punctual) and
// emissive surfaces as area lights (see src/scene/emitters.h for the model; the
// C++ twin of emitterFactor() is scene::emitterIrradianceFactor, tested against
// closed forms). BRDF: Lambert + GGX (Trowbridge-Reitz) with the height-correlated
// Smith visibility and Schlick's Fresnel, as in the glTF 2.0 spec appendix B.
#ifndef VOXGI_LIGHTING_GLSL
#define VOXGI_LIGHTING_GLSL

#include "brdf_shared.h"

// One edge's term of Lambert's formula for the irradiance of a polygon of unit
// radiance: theta (gamma . n), for the edge from pa to pb (relative to the receiver).
float lambertEdge(vec3 pa, vec3 pb, vec3 n) {
  float la = length(pa);
  float lb = length(pb);
  if (!(la > 1e-30) || !(lb > 1e-30)) return 0.0;  // a corner at the receiver itself
  vec3 a = pa / la;
  vec3 b = pb / lb;
  vec3 c = cross(a, b);
  float s = length(c);
  if (!(s >= 1e-12)) return 0.0;
  return atan(s, dot(a, b)) * dot(c / s, n);
}

// The term of edge a -> b (heights da, db above the tangent plane) clipped to the
// upper hemisphere, without branches: an end below the plane moves to where the
// edge crosses it. Records that crossing as the polygon's exit (a above, b below)
// or entry (a below, b above) point on the plane.
float lambertClippedEdge(vec3 a, vec3 b, float da, float db, vec3 n, inout vec3 exitPoint,
                         inout vec3 entryPoint) {
  vec3 x = a + (b - a) * (da / (da - db));  // used only when the signs differ
  bool aboveA = da > 0.0, aboveB = db > 0.0;
  exitPoint = aboveA && !aboveB ? x : exitPoint;
  entryPoint = !aboveA && aboveB ? x : entryPoint;
  float term = lambertEdge(aboveA ? a : x, aboveB ? b : x, n);
  return aboveA || aboveB ? term : 0.0;
}

// Irradiance per unit emitted radiance at p (normal n) from one emitter.
float emitterFactor(GpuEmitter e, vec3 p, vec3 n) {
  if (uint(e.a.w) == kEmitterCluster) {
    vec3 toC = e.a.xyz - p;
    float d2 = dot(toC, toC);
    vec3 w = toC * inversesqrt(max(d2, 1e-30));
    float cosE = -dot(e.b.xyz, w);
    if (e.radiance.w > 0.5) cosE = abs(cosE);
    float cosR = dot(n, w);
    if (cosE <= 0.0 || cosR <= 0.0) return 0.0;
    return e.b.w * cosE * cosR / (d2 + e.b.w / kPi);
  }
  vec3 en = normalize(cross(e.b.xyz - e.a.xyz, e.c.xyz - e.a.xyz));
  if (e.radiance.w < 0.5 && dot(en, p - e.a.xyz) <= 0.0) return 0.0;
  // The triangle clipped to the receiver's upper hemisphere: each edge keeps its
  // part above the tangent plane, and where the triangle dips below, the clipped
  // polygon closes along the plane from the exit point to the entry point. Written
  // without arrays or loops (a dynamically indexed local array is slow on a SIMD
  // software rasterizer).
  vec3 a = e.a.xyz - p, b = e.b.xyz - p, c = e.c.xyz - p;
  float da = dot(a, n), db = dot(b, n), dc = dot(c, n);
  if (da <= 0.0 && db <= 0.0 && dc <= 0.0) return 0.0;
  vec3 exitPoint = vec3(0.0), entryPoint = vec3(0.0);
  float sum = lambertClippedEdge(a, b, da, db, n, exitPoint, entryPoint) +
              lambertClippedEdge(b, c, db, dc, n, exitPoint, entryPoint) +
              lambertClippedEdge(c, a, dc, da, n, exitPoint, entryPoint);
  if (da <= 0.0 || db <= 0.0 || dc <= 0.0) sum += lambertEdge(exitPoint, entryPoint, n);
  return 0.5 * abs(sum);
}

vec3 emitterCenter(GpuEmitter e) {
  return uint(e.a.w) == kEmitterCluster ? e.a.xyz : (e.a.xyz + e.b.xyz + e.c.xyz) / 3.0;
}

float emitterArea(GpuEmitter e) {
  return uint(e.a.w) == kEmitterCluster ? e.b.w
                                        : 0.5 * length(cross(e.b.xyz - e.a.xyz, e.c.xyz - e.a.xyz));
}

struct Surface {
  vec3 p;
  vec3 n;
  vec3 v;        // towards the viewer
  vec3 diffuse;  // albedo (1 - metallic) x base colour
  vec3 f0;
  float alpha;     // GGX alpha = roughness^2
  float specular;  // 1: the glTF BRDF; 0: pure Lambert (isLambertian)
};

// Reflected radiance for irradiance `irradiance` arriving from direction l.
// `alphaMin` widens the lobe for lights of finite size (Karis 2013).
vec3 shade(Surface s, vec3 l, vec3 irradiance, float alphaMin) {
  float nl = dot(s.n, l);
  if (nl <= 0.0) return vec3(0.0);
  float nv = max(dot(s.n, s.v), 1e-4);
  vec3 h = normalize(l + s.v);
  float nh = max(dot(s.n, h), 0.0);
  float vh = max(dot(s.v, h), 0.0);
  float alpha = clamp(max(s.alpha, alphaMin), 2e-3, 1.0);
  vec3 f = s.specular * schlickFresnel(s.f0, vh);
  vec3 spec = f * ggxD(nh, alpha) * smithVisibility(nl, nv, alpha);
  vec3 diff = (1.0 - f) * s.diffuse / kPi;
  return (diff + spec) * irradiance;
}

vec3 punctualLight(GpuLight light, Surface s) {
  uint type = uint(light.positionType.w);
  vec3 l;
  float atten = 1.0;
  if (type == kLightDirectional) {
    l = -normalize(light.directionRange.xyz);
  } else {
    vec3 d = light.positionType.xyz - s.p;
    float dist2 = max(dot(d, d), 1e-30);
    l = d * inversesqrt(dist2);
    atten = 1.0 / dist2;
    float range = light.directionRange.w;
    if (range > 0.0) {  // the glTF spec's recommended smooth window
      float r = sqrt(dist2) / range;
      atten *= clamp(1.0 - r * r * r * r, 0.0, 1.0);
    }
    if (type == kLightSpot) {
      float cd = dot(normalize(light.directionRange.xyz), -l);
      atten *= smoothstep(light.cone.y, light.cone.x, cd);
    }
  }
  float nl = dot(s.n, l);
  if (nl <= 0.0 || atten <= 0.0) return vec3(0.0);
  return shade(s, l, light.radiance.rgb * atten * nl, 0.0);
}

vec3 areaLight(GpuEmitter e, Surface s) {
  float g = emitterFactor(e, s.p, s.n);
  if (g <= 0.0) return vec3(0.0);
  vec3 toC = emitterCenter(e) - s.p;
  float d = length(toC);
  vec3 l = toC / max(d, 1e-30);
  float radius = sqrt(emitterArea(e) / kPi);
  // A light near the horizon may have part of it above: keep l above the surface.
  if (dot(s.n, l) <= 1e-3) l = normalize(l + s.n * (1e-3 - dot(s.n, l)));
  return shade(s, l, e.radiance.rgb * g, clamp(0.5 * radius / max(d, 1e-30), 0.0, 1.0));
}

#endif  // VOXGI_LIGHTING_GLSL
