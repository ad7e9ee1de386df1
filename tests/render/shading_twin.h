// One case of the shading twin test, in the common subset of GLSL and C++:
// tests/render/shading_twin.comp runs it on the GL device, and
// tests/render/shading_twin_gltest.cpp runs the C++ build and compares. Every
// shared function of sampling_shared.h, brdf_shared.h and pathtrace_shading.h is
// called on the case's inputs; the results fill kTwinOutputs vec4s.
#ifndef VOXGI_TESTS_SHADING_TWIN_H
#define VOXGI_TESTS_SHADING_TWIN_H

#include "pathtrace_shading.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

VOXGI_CONST uint kTwinInputs = 5u;
VOXGI_CONST uint kTwinOutputs = 11u;

// in[0]: unit normal, metallic | in[1]: unit wo, roughness | in[2]: unit wi, u0
// in[3]: base colour, u1 | in[4]: point, seed (bits)
VOXGI_FN void twinCase(VOXGI_TABLES_PARAM vec4 in0, vec4 in1, vec4 in2, vec4 in3, vec4 in4,
                       uint emitterCount, GpuLight light, uvec4 texture, VOXGI_OUT(vec4) o0,
                       VOXGI_OUT(vec4) o1, VOXGI_OUT(vec4) o2, VOXGI_OUT(vec4) o3,
                       VOXGI_OUT(vec4) o4, VOXGI_OUT(vec4) o5, VOXGI_OUT(vec4) o6,
                       VOXGI_OUT(vec4) o7, VOXGI_OUT(vec4) o8, VOXGI_OUT(vec4) o9,
                       VOXGI_OUT(vec4) o10) {
  vec3 n = vec3(in0);
  vec3 wo = vec3(in1);
  vec3 wi = vec3(in2);
  vec3 base = vec3(in3);
  vec3 p = vec3(in4);
  float metallic = in0.w;
  float roughness = in1.w;
  vec2 u = vec2(in2.w, in3.w);
  uint seed = floatBitsToUint(in4.w);

  uint rng = pcgHash(seed);
  float r0 = pcgNext01(rng);
  float r1 = pcgNext01(rng);
  o0 = vec4(uintBitsToFloat(pcgHash(seed)), r0, r1, uintBitsToFloat(rng));

  vec3 t;
  vec3 bt;
  basis(n, t, bt);
  o1 = vec4(cosineSample(n, u), t.x + bt.y);

  Bsdf b = makeBsdf(base, metallic, roughness, max(dot(n, wo), 0.0f));
  o2 = vec4(sampleVndf(vec3(dot(wo, t), dot(wo, bt), dot(wo, n)), b.alpha, u), b.specularChance);

  float pdf;
  vec3 f = evalBsdf(b, n, wo, wi, pdf);
  o3 = vec4(f, pdf);

  vec3 sampled;
  bool ok = sampleBsdf(b, n, wo, rng, sampled);
  o4 = vec4(sampled, ok ? float(b.kind) + 1.0f : -1.0f);

  EmitterSample es = sampleEmitter(VOXGI_TABLES_ARG p, emitterCount, u.x, u.y, r0);
  o5 = vec4(es.wi, es.pdfLight);
  o6 = vec4(es.radiance, es.dist);

  PunctualSample ps = samplePunctual(light, p);
  o7 = vec4(ps.radiance, min(ps.dist, 1e6f));

  // Every combination of the table's flags (sRGB, nearest, each axis's wrap mode),
  // drawn from the seed; uv in [-1, 2) reaches outside the texture.
  uvec4 wrapped = uvec4(texture.x, texture.y, texture.z, texture.w | ((seed >> 3u) & 63u));
  o8 = sampleTexture(VOXGI_TABLES_ARG wrapped, u * 3.0f - 1.0f);

  o9 = vec4(luminance(base), powerHeuristic(pdf, r1), emissionMisWeight(pdf, r0, r1 + 0.5f, u.x),
            smithG1(max(dot(n, wo), 0.0f), b.alpha) + ggxD(u.y, b.alpha) * 1e-3f +
                smithVisibility(u.x, u.y, b.alpha));

  o10 = vec4(metallicF0(base, metallic), isSpecular(metallic, roughness) ? 1.0f : 0.0f);
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_TESTS_SHADING_TWIN_H
