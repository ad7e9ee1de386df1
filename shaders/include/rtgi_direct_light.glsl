// Direct light reflected at a surface towards its viewer, as rtgi estimates it at
// the pixels (rtgi_direct.comp) and at the hits of their reflected rays
// (rtgi_specular.comp). Punctual lights: their exact contribution x visibility,
// each with its shadow ray, or with many one drawn in proportion to its
// contribution. Emissive surfaces: one emitter drawn in proportion to its exact
// unshadowed contribution (few: RTGI_EMITTERS_EXACT) or from the light tree
// (light_tree_shared.h) in proportion to a bound on it (many:
// RTGI_EMITTERS_SAMPLED), one direction towards it and one shadow ray; the
// Lambert part by light sampling, the GGX highlight as the exact unshadowed one x
// that visibility (directLight below).
// Accumulation over frames turns the visibility samples into soft shadows.
// VOXGI_NO_SHADOWS: no shadow ray, and the exact sum over the emitters;
// VOXGI_NO_EMISSION: no emitters. RTGI_LIGHTS: the scene has punctual lights;
// RTGI_LIGHTS_SAMPLED: more than RtgiPass::Settings::exactLights of them, one drawn
// per pixel and frame.
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
// Candidates drawn from the light tree for each emitter sample (directLight).
#ifndef RTGI_EMITTER_CANDIDATES
#define RTGI_EMITTER_CANDIDATES 4
#endif
const int kRtgiEmitterCandidates = RTGI_EMITTER_CANDIDATES;
// Where the light tree's walk stops and draws among a node's emitters, each weighed
// by its own bound (pickLightTree): fewer at the indirect rays' hits and where
// candidates are resampled (RtgiPass::lightDefines).
#ifndef RTGI_LEAF_DRAW
#define RTGI_LEAF_DRAW kLightTreeLeafDraw
#endif
const float kRtgiLeafDraw = RTGI_LEAF_DRAW;
layout(std430, binding = kLightTreeBinding) readonly buffer LightTree { GpuLightNode lightTree[]; };
GpuLightNode lightTreeNode(int i) { return lightTree[i]; }
#endif

#ifdef RTGI_EMITTER_TILES
// Where the pixels draw their emitters from light tiles (rtgi_light_tiles.comp),
// rtgi_direct.comp, the one stage that does, defines the draw.
int pickTileEmitter(float u, out float pmf, out GpuLightNode leaf);
#endif

// The Lambert part of the light arriving at s from emitter e along l, divided by the
// direction's pdf: with the exact highlight sum, what directLight scales by
// visibility.
vec3 emitterDiffuseSample(GpuEmitter e, Surface s, vec3 l, float pdf) {
  return shadeDiffuse(s, l, e.radiance * max(dot(s.n, l), 0.0)) / pdf;
}

// What the shadows stage's reservoirs and directLight weigh emitter k by at s: the
// luminance of its exact unshadowed contribution (lighting.glsl), and that
// contribution's highlight in `spec`.
float emitterTarget(int k, Surface s, out vec3 spec) {
  return luminance(areaLightParts(emitters[k], s, spec));
}

// From this GGX alpha up (roughness 0.5), a surface's highlight from an emitter is
// estimated along the emitter's drawn direction, as its Lambert part is: unbiased,
// and a lobe this wide varies little over the directions drawn. Sharper highlights
// keep the representative point (areaLightParts), smooth but biased: on the hall
// gallery's wood (roughness 0.7) under the skylight it was 35% too bright in places.
const float kSampledHighlightAlpha = 0.25;

bool sampledHighlight(Surface s) { return s.specular > 0.0 && s.alpha >= kSampledHighlightAlpha; }

// Highlights shared with the reflected rays (RTGI_HIGHLIGHT_MIS). Where the specular
// stage traces a ray drawn from the GGX lobe (rtgi_specular.comp: glossy pixels,
// with the BVH), a highlight has two estimators: the direct stage's light sample,
// and that ray meeting the emitter. Each weighs its sample by its share of the
// balance heuristic (Veach and Guibas 1995, "Optimally combining sampling techniques
// for Monte Carlo rendering"), so together they are unbiased: the light sample
// carries the highlights of small emitters, the lobe's ray those of emitters large
// next to the lobe, where a light sample would mostly miss a sharp lobe and a
// representative point (areaLightParts) is biased (the hall's bronze, roughness
// 0.35, came out 26-31% too bright under the skylight).
// The two shares must add to 1 for each direction, not follow the true pdfs: the
// light's is taken as uniform over the emitter triangle's solid angle (which both
// stages compute alike from the pixel's point), not as the draw's, which reservoirs
// and the light tree make intractable. Clusters, lit as disks, keep their light
// sample whole; their facets carry a negated pdf in the BVH, and the ray skips them.
// Set by rtgi_direct.comp per pixel; hits of other rays keep their own estimate.
bool highlightMis = false;
// Set by rtgi_direct.comp where no specular stage shares a pixel's highlights (a plan
// without the specular effect, or with cones or voxel reflections, which do not see
// emitters: RTGI_HIGHLIGHT_SAMPLED): the light sample carries them whole, unbiased,
// where the representative point is not.
bool highlightSampled = false;

// The lobe ray's weight against the light sample's in that balance heuristic
// (RtgiPass::Settings::lobeShareWeight), as Veach and Guibas weigh each technique's
// pdf by its count of samples: the lobe traces kFirstLobeRays rays in a pixel's first
// frames, and the light sample's pdf, taken as uniform over the triangle, is above
// the draw's (which picks the triangle among others first). On the hall's bronze
// knot, 1 left the skylight's highlight mostly to light samples, which land in the
// lobe seldom and bright: the knot's variance at one frame 0.234 with 1, 0.112 with
// 4 (measurements.md#2026-12-07-glossy-highlight-shares).
#ifndef RTGI_LOBE_SHARE
#define RTGI_LOBE_SHARE 4.0
#endif
const float kLobeShare = RTGI_LOBE_SHARE;

// The light sample's share of the highlight along unit l, towards a triangle of
// solid angle `omega` from s.p; the ray's share is 1 minus it.
float highlightLightShare(Surface s, vec3 l, float omega) {
  float nv = max(dot(s.n, s.v), 1e-4);
  float alpha = max(s.alpha, 1e-3);  // as the specular stage draws its lobe
  vec3 h = normalize(l + s.v);
  float lobePdf = smithG1(nv, alpha) * ggxD(max(dot(s.n, h), 0.0), alpha) / (4.0 * nv);
  return 1.0 / (1.0 + kLobeShare * omega * lobePdf);
}

// The solid angle of the triangle a, b, c seen from p.
float triangleSolidAngle(vec3 a, vec3 b, vec3 c, vec3 p) {
  return sphericalTriangleArea(normalize(a - p), normalize(b - p), normalize(c - p));
}

// Emitter k's light at s, shadowed: one direction towards it, its Lambert part by
// light sampling x `weight` (1 / the probability of drawing k, or a reservoir's
// contribution weight), plus the highlight: `spec` (already weighted), or where
// sampledHighlight, the GGX lobe along that direction x `weight` (and, where
// highlightMis, x its share: above); x the visibility of that direction's point.
vec3 emitterShade(int k, float weight, vec3 spec, Surface s, vec3 o, vec3 ng) {
  GpuEmitter e = emitters[k];
  vec3 l;
  float dist;
  float pdf = sampleEmitterDirection(e, s.p, s.n, vec2(rand01(), rand01()), l, dist);
  if (!(pdf > 0.0)) return vec3(0.0);
  vec3 c;
  if (highlightMis || highlightSampled) {
    vec3 irradiance = e.radiance * max(dot(s.n, l), 0.0);
    float share = !highlightMis || e.kind == kEmitterCluster
                      ? 1.0
                      : highlightLightShare(s, l, triangleSolidAngle(e.a, e.b, e.c, s.p));
    c = (shadeDiffuse(s, l, irradiance) + shadeSpecular(s, l, irradiance, 0.0) * share) / pdf *
        weight;
  } else {
    c = sampledHighlight(s) ? shade(s, l, e.radiance * max(dot(s.n, l), 0.0), 0.0) / pdf * weight
                            : emitterDiffuseSample(e, s, l, pdf) * weight + spec;
  }
  vec3 d = s.p + l * dist - o;
  float len = length(d);
  if (!(dot(d, ng) >= 0.0) || !any(greaterThan(c, vec3(0.0)))) return vec3(0.0);
  return c * (len > 0.0 ? shadowRay(o, d / len, len, true, emitterSlack(e)) : 1.0);
}

// `ng`: the surface's own normal where a normal map tilts s.n, else 0: light from
// below it does not count (the leak rule, normal_map_shared.h).
vec3 punctualDirect(Surface s, vec3 o, vec3 ng) {
  vec3 result = vec3(0.0);
#if defined(RTGI_LIGHTS_SAMPLED)
  {
    // Many punctual lights: one drawn in proportion to its exact unshadowed
    // contribution c_k (the same one-pass draw as the emitters' below), and its
    // c_k x visibility / P_k, P_k = c_k / sum: the unshadowed sum where the light is
    // seen, unbiased, at the cost of one shadow ray however many lights there are.
    int lightCount = int(rtgi.lightCount);
    float total = 0.0;
    float picked = 0.0;
    vec3 pickedLight = vec3(0.0);
    float u = rand01();
    int pick = -1;
    for (int k = 0; k < lightCount; ++k) {
      vec3 c = punctualLight(lights[k], s);
      float w = luminance(c);
      if (!(w > 0.0)) continue;
      vec3 l;
      float dist;
      punctualDirection(lights[k], s.p, l, dist);
      if (dot(l, ng) < 0.0) continue;
      total += w;
      float q = w / total;
      if (u < q) {
        pick = k;
        picked = w;
        pickedLight = c;
        u = u / q;
      } else {
        u = (u - q) / (1.0 - q);
      }
    }
    if (pick >= 0) {
      vec3 l;
      float dist;
      punctualDirection(lights[pick], s.p, l, dist);
      result += pickedLight * (total / picked) * shadowRay(o, l, dist, false, 0.0);
    }
  }
#elif defined(RTGI_LIGHTS)
  int lightCount = int(rtgi.lightCount);
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
  return result;
}

vec3 directLight(Surface s, vec3 o, vec3 ng) {
  vec3 result = punctualDirect(s, o, ng);
#ifndef VOXGI_NO_EMISSION
  int emitterCount = int(rtgi.emitterCount);
#ifdef VOXGI_NO_SHADOWS
  // Unshadowed: the exact sum of every emitter's contribution.
  for (int k = 0; k < emitterCount; ++k) result += areaLight(emitters[k], s);
  emitterCount = 0;
#endif
#if defined(RTGI_EMITTERS_EXACT) || defined(RTGI_EMITTERS_SAMPLED)
  // One emitter k is picked with probability P_k, one direction l towards it with
  // solid-angle pdf p(l), and one shadow ray traced to the point l meets. The Lambert
  // part is the light-sampling estimate L (1 - F) albedo/pi cos / (P_k p(l)) x
  // visibility, unbiased however the emitter is shadowed. The highlight is the exact
  // unshadowed one (representative point) x that visibility: it stays smooth where a
  // sampled GGX lobe would sparkle, and is biased only in partial shadow.
  vec3 specular = vec3(0.0);
  int pick = -1;
#if defined(RTGI_EMITTERS_EXACT)
  {
    // Picked in proportion to their unshadowed contribution w_k. One pass, no array:
    // emitter k replaces the pick with probability w_k / (w_0 + ... + w_k), which
    // leaves each picked in proportion to w_k; the one uniform number is rescaled
    // after each decision, so it stays uniform.
    float total = 0.0;
    float picked = 0.0;
    float u = rand01();
    for (int k = 0; k < emitterCount; ++k) {
      vec3 spec;
      float w = luminance(areaLightParts(emitters[k], s, spec));
      specular += spec;
      if (!(w > 0.0)) continue;
      total += w;
      float q = w / total;
      if (u < q) {
        pick = k;
        picked = w;
        u = u / q;
      } else {
        u = (u - q) / (1.0 - q);
      }
    }
    float pmf = pick >= 0 ? picked / total : 0.0;
#else
  {
    // Resampled importance sampling (Talbot et al. 2005, as ReSTIR DI's candidate
    // stage, Bitterli et al. 2020): kRtgiEmitterCandidates emitters k_i drawn from
    // the light tree with probabilities P_i (in proportion to a bound on what they
    // send here, loose for a node of emitters far apart), each weighed by
    // w_i = h(k_i) / P_i, h the luminance of its exact unshadowed contribution; one
    // kept in proportion to w_i (streaming, one number each). Its estimate is then
    // divided by h(k) M / sum(w_i) in place of a probability: unbiased, as h > 0
    // wherever an emitter can send light, and as near the exact unshadowed draw as
    // the candidates allow, where a lamp drawn with a small P_i that lights the point
    // strongly would be a firefly.
    float pmf = 0.0;
    float wSum = 0.0;
    float pickedH = 0.0;
    int candidates = emitterCount > 0 ? kRtgiEmitterCandidates : 0;  // 0: summed above
    for (int i = 0; i < candidates; ++i) {
      float p;
      float u = rand01();
#ifdef RTGI_EMITTER_TILES
      // Drawn from the pixel's light tile, and weighed by the emitter's own bound at
      // the pixel (what the draw without tiles is in proportion to), not by its
      // exact contribution (areaLightParts), which for a triangle costs many times
      // as much: resampling the tile's draw by the bound approaches that draw. The
      // bound is above 0 wherever the emitter can send light, so the estimate stays
      // unbiased.
      GpuLightNode leaf;
      int k = pickTileEmitter(u, p, leaf);
      float r = rand01();
      if (k < 0 || !(p > 0.0)) continue;
      float h = lightNodeImportance(leaf, s.p, s.n);
#else
      int k = pickLightTree(u, floatBitsToUint(rand01()), s.p, s.n, kRtgiLeafDraw, p);
      float r = rand01();
      if (k < 0 || !(p > 0.0)) continue;
      vec3 spec;
      float h = emitterTarget(k, s, spec);
#endif
      if (!(h > 0.0)) continue;
      float w = h / p;
      wSum += w;
      if (r * wSum < w) {
        pick = k;
        pickedH = h;
#ifndef RTGI_EMITTER_TILES
        specular = spec;
#endif
      }
    }
    if (pick >= 0) {
      pmf = pickedH * float(kRtgiEmitterCandidates) / wSum;
#ifdef RTGI_EMITTER_TILES
      emitterTarget(pick, s, specular);
#endif
      specular /= pmf;
    }
#endif
    if (pick >= 0 && pmf > 0.0) result += emitterShade(pick, 1.0 / pmf, specular, s, o, ng);
  }
#endif
#endif
  return result;
}

#endif  // VOXGI_RTGI_DIRECT_LIGHT_GLSL
