// Materials, written once for GLSL and C++ (see shared_fn.h): the BRDF terms that
// raster, rtgi and the voxel light use through lighting.glsl, and the path
// tracer's BSDF (evaluation, pdf, sampling) that both of its devices use.
// Twin test: tests/render/shading_twin_gltest.cpp.
//
// Three kinds, as in scenes/reference_scenes.md: metallic 0 + roughness 1 is pure
// Lambert (albedo = base colour); metallic 1 + roughness 0 is a perfect mirror of
// reflectance = base colour, no Fresnel; anything else is the glTF 2.0
// metallic-roughness BRDF (spec appendix B): Lambert + GGX (Trowbridge-Reitz) with
// the height-correlated Smith visibility and Schlick's Fresnel.
#ifndef VOXGI_BRDF_SHARED_H
#define VOXGI_BRDF_SHARED_H

#include "sampling_shared.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// Rec. 709 luminance of linear RGB.
VOXGI_FN float luminance(vec3 c) { return dot(c, vec3(0.2126f, 0.7152f, 0.0722f)); }

// The reference scenes' convention (scenes/reference_scenes.md), which the path
// tracer follows: metallic 0 with roughness 1 is pure Lambert (albedo = base colour,
// no Fresnel, no specular lobe), not the glTF BRDF at its roughest.
VOXGI_FN bool isLambertian(float metallic, float roughness) {
  return metallic <= 0.0f && roughness >= 1.0f;
}

// Dielectrics rougher than this reflect too little, too blurred, to trace.
VOXGI_CONST float kGlossyRoughness = 0.6f;

// The rule for which materials are specular: whether a material reflects enough,
// sharply enough, for rtgi's specular stage to trace its reflection. Metals, and
// dielectrics smoother than kGlossyRoughness. rtgi_specular.comp applies it per
// pixel, scene::isSpecular per material (to plan the stage).
VOXGI_FN bool isSpecular(float metallic, float roughness) {
  return metallic > 0.5f || roughness < kGlossyRoughness;
}

// Reflectance at normal incidence (Schlick's F0): 4% for a dielectric, the base
// colour for a metal, blended by metallic (glTF 2.0 spec appendix B).
VOXGI_FN vec3 metallicF0(vec3 baseColor, float metallic) {
  return mix(vec3(0.04f), baseColor, metallic);
}

// Schlick's Fresnel at the cosine c between the view (or light) and the normal
// that reflects it. A cosine a rounding above 1 (the half vector of a light seen
// straight along the view: dot(v, normalize(v + v)) can be 1 + 1 ulp) reads as 1:
// GLSL's pow of a negative base is undefined, and llvmpipe returns NaN.
VOXGI_FN vec3 schlickFresnel(vec3 f0, float c) {
  return f0 + (1.0f - f0) * pow(max(1.0f - c, 0.0f), 5.0f);
}

VOXGI_FN float ggxD(float nh, float alpha) {
  float a2 = alpha * alpha;
  float d = nh * nh * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

// Height-correlated Smith visibility G2 / (4 n.l n.v).
VOXGI_FN float smithVisibility(float nl, float nv, float alpha) {
  float a2 = alpha * alpha;
  float gv = nl * sqrt(nv * nv * (1.0f - a2) + a2);
  float gl = nv * sqrt(nl * nl * (1.0f - a2) + a2);
  float s = gv + gl;
  return s > 0.0f ? 0.5f / s : 0.0f;
}

VOXGI_FN float smithG1(float nv, float alpha) {
  float a2 = alpha * alpha;
  return 2.0f * nv / (nv + sqrt(a2 + (1.0f - a2) * nv * nv));
}

// Veach 1997, the power heuristic (beta 2).
VOXGI_FN float powerHeuristic(float a, float b) {
  float a2 = a * a;
  return a2 / (a2 + b * b);
}

VOXGI_CONST int kBsdfLambert = 0;
VOXGI_CONST int kBsdfMirror = 1;
VOXGI_CONST int kBsdfGgx = 2;

struct Bsdf {
  int kind;  // kBsdf*
  vec3 base;
  vec3 diffuse;
  vec3 f0;
  float alpha;
  float specularChance;  // probability of sampling the GGX lobe (kBsdfGgx only)
};

// The BSDF of a material seen at n.v = nv.
VOXGI_FN Bsdf makeBsdf(vec3 baseColor, float metallic, float roughness, float nv) {
  Bsdf b;
  b.base = baseColor;
  b.kind = isLambertian(metallic, roughness)         ? kBsdfLambert
           : (metallic >= 1.0f && roughness <= 0.0f) ? kBsdfMirror
                                                     : kBsdfGgx;
  b.diffuse = b.base * (1.0f - metallic);
  b.f0 = metallicF0(b.base, metallic);
  b.alpha = clamp(roughness * roughness, 1e-3f, 1.0f);
  b.specularChance = 1.0f;
  if (b.kind != kBsdfGgx) return b;  // the lobe choice is the GGX kind's alone
  vec3 fv = schlickFresnel(b.f0, nv);
  float ws = luminance(fv);
  float wd = luminance(b.diffuse) * (1.0f - ws);
  b.specularChance = ws + wd > 0.0f ? clamp(ws / (ws + wd), 0.1f, 1.0f) : 1.0f;
  if (wd <= 0.0f) b.specularChance = 1.0f;
  return b;
}

// BSDF x cos(wi) and the pdf (solid angle) of sampling wi, for non-delta kinds.
VOXGI_FN vec3 evalBsdf(Bsdf b, vec3 n, vec3 wo, vec3 wi, VOXGI_OUT(float) pdf) {
  float nl = dot(n, wi);
  float nv = dot(n, wo);
  pdf = 0.0f;
  if (nl <= 0.0f || nv <= 0.0f) return vec3(0.0f);
  if (b.kind == kBsdfLambert) {
    pdf = nl / kPi;
    return b.base * (nl / kPi);
  }
  vec3 h = normalize(wi + wo);
  float nh = max(dot(n, h), 0.0f);
  float vh = max(dot(wo, h), 0.0f);
  float d = ggxD(nh, b.alpha);
  vec3 f = schlickFresnel(b.f0, vh);
  vec3 spec = f * d * smithVisibility(nl, nv, b.alpha);
  vec3 diff = (1.0f - f) * b.diffuse / kPi;
  // Visible-normal sampling: pdf(wi) = G1(wo) D(h) / (4 n.wo).
  float pdfSpec = smithG1(nv, b.alpha) * d / (4.0f * nv);
  pdf = b.specularChance * pdfSpec + (1.0f - b.specularChance) * nl / kPi;
  return (spec + diff) * nl;
}

// Samples wi for a non-delta kind from the stream `rng` (two numbers, three for
// GGX); false when the sample is below the surface.
VOXGI_FN bool sampleBsdf(Bsdf b, vec3 n, vec3 wo, VOXGI_INOUT(uint) rng, VOXGI_OUT(vec3) wi) {
  float u0 = pcgNext01(rng);
  float u1 = pcgNext01(rng);
  if (b.kind == kBsdfLambert || pcgNext01(rng) >= b.specularChance) {
    wi = cosineSample(n, vec2(u0, u1));
  } else {
    vec3 t;
    vec3 bt;
    basis(n, t, bt);
    vec3 ve = vec3(dot(wo, t), dot(wo, bt), dot(wo, n));
    vec3 m = sampleVndf(ve, b.alpha, vec2(u0, u1));
    vec3 h = normalize(t * m.x + bt * m.y + n * m.z);
    wi = reflect(-wo, h);
  }
  return dot(n, wi) > 0.0f;
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_BRDF_SHARED_H
