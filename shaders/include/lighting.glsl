// Direct lighting without visibility: punctual lights (KHR_lights_punctual) and
// emissive surfaces as area lights (see src/scene/emitters.h for the model; the
// form factor is emitter_shared.h's, which scene::emitterIrradianceFactor shares
// and the C++ tests hold to closed forms). BRDF: Lambert + GGX (Trowbridge-Reitz)
// with the height-correlated Smith visibility and Schlick's Fresnel, as in the
// glTF 2.0 spec appendix B.
#ifndef VOXGI_LIGHTING_GLSL
#define VOXGI_LIGHTING_GLSL

#include "brdf_shared.h"
#include "emitter_shared.h"

// Irradiance per unit emitted radiance at p (normal n) from one emitter.
float emitterFactor(GpuEmitter e, vec3 p, vec3 n) {
  bool twoSided = e.twoSided != 0u;
  if (e.kind == kEmitterCluster) return clusterEmitterFactor(e.a, e.b, e.area, twoSided, p, n);
  return triangleEmitterFactor(e.a, e.b, e.c, twoSided, p, n);
}

vec3 emitterCenter(GpuEmitter e) {
  return e.kind == kEmitterCluster ? e.a : (e.a + e.b + e.c) / 3.0;
}

float emitterArea(GpuEmitter e) {
  return e.kind == kEmitterCluster ? e.area : 0.5 * length(cross(e.b - e.a, e.c - e.a));
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

// The two parts of the reflected radiance for irradiance `irradiance` arriving from
// direction l: the Lambert part (what the specular layer lets through) and the GGX
// highlight. `alphaMin` widens the lobe for lights of finite size (Karis 2013).
vec3 shadeDiffuse(Surface s, vec3 l, vec3 irradiance) {
  if (dot(s.n, l) <= 0.0) return vec3(0.0);
  float vh = max(dot(s.v, normalize(l + s.v)), 0.0);
  vec3 f = s.specular * schlickFresnel(s.f0, vh);
  return (1.0 - f) * s.diffuse / kPi * irradiance;
}

vec3 shadeSpecular(Surface s, vec3 l, vec3 irradiance, float alphaMin) {
  float nl = dot(s.n, l);
  if (nl <= 0.0) return vec3(0.0);
  float nv = max(dot(s.n, s.v), 1e-4);
  vec3 h = normalize(l + s.v);
  float nh = max(dot(s.n, h), 0.0);
  float vh = max(dot(s.v, h), 0.0);
  float alpha = clamp(max(s.alpha, alphaMin), 2e-3, 1.0);
  vec3 f = s.specular * schlickFresnel(s.f0, vh);
  return f * ggxD(nh, alpha) * smithVisibility(nl, nv, alpha) * irradiance;
}

vec3 shade(Surface s, vec3 l, vec3 irradiance, float alphaMin) {
  return shadeDiffuse(s, l, irradiance) + shadeSpecular(s, l, irradiance, alphaMin);
}

// The directional albedo of the GGX lobe (Schlick's Fresnel, Smith's masking) seen
// at n.v = nv, as f0 x a + b: B. Karis's analytic fit of the split-sum integral
// ("Physically Based Shading on Mobile", 2014), roughness as in glTF.
vec2 specularAlbedoFit(float nv, float roughness) {
  const vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022);
  const vec4 c1 = vec4(1.0, 0.0425, 1.04, -0.04);
  vec4 r = roughness * c0 + c1;
  float a004 = min(r.x * r.x, exp2(-9.28 * nv)) * r.x + r.y;
  return vec2(-1.04, 1.04) * a004 + r.zw;
}

// What s reflects towards s.v of light arriving evenly from every direction: the
// GGX lobe's albedo, and the Lambert part less what that lobe takes. The diffuse
// albedo alone for pure Lambert.
vec3 directionalAlbedo(Surface s, float roughness) {
  if (s.specular == 0.0) return s.diffuse;
  vec2 ab = specularAlbedoFit(clamp(dot(s.n, s.v), 0.0, 1.0), roughness);
  vec3 spec = clamp(s.f0 * ab.x + ab.y, 0.0, 1.0);
  return s.diffuse * (1.0 - spec) + spec;
}

// The voxels reflect their light as Lambert surfaces of the base colour; a glTF
// material reflects light that arrives from all about by its directional albedo
// towards s.v (a rough tiled floor seen at a grazing angle sends less than its base
// colour says). Their ratio, per channel, turns a voxel's light into the material's:
// 1 for pure Lambert. Used where a pixel's ray meets the material; the leaves'
// gather does not (octree_bounce.comp): the light there comes mostly from above,
// and the GGX lobe sends little of it towards the grazing directions a neighbour
// sees the floor from, less than light from all about would (the night hall came out
// 0.7% too bright with it; docs/history.md).
vec3 voxelToMaterial(Surface s, float roughness, vec3 base) {
  if (s.specular == 0.0) return vec3(1.0);
  return directionalAlbedo(s, roughness) / max(base, vec3(1e-4));
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

// An emitter's unshadowed light reflected at s: the Lambert part exactly (the form
// factor), the highlight from a representative point at its centre with the lobe
// widened by its size (Karis 2013). Returns their sum, and the highlight alone in
// `spec`.
vec3 areaLightParts(GpuEmitter e, Surface s, out vec3 spec) {
  spec = vec3(0.0);
  float g = emitterFactor(e, s.p, s.n);
  if (g <= 0.0) return vec3(0.0);
  vec3 toC = emitterCenter(e) - s.p;
  float d = length(toC);
  vec3 l = toC / max(d, 1e-30);
  float radius = sqrt(emitterArea(e) / kPi);
  // A light near the horizon may have part of it above: keep l above the surface.
  if (dot(s.n, l) <= 1e-3) l = normalize(l + s.n * (1e-3 - dot(s.n, l)));
  vec3 irradiance = e.radiance * g;
  spec = shadeSpecular(s, l, irradiance, clamp(0.5 * radius / max(d, 1e-30), 0.0, 1.0));
  return shadeDiffuse(s, l, irradiance) + spec;
}

vec3 areaLight(GpuEmitter e, Surface s) {
  vec3 spec;
  return areaLightParts(e, s, spec);
}

#endif  // VOXGI_LIGHTING_GLSL
