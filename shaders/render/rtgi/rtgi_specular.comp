#version 450 core
// rtgi stage "specular": light along the reflection. Mirrors (roughness below
// kMirrorRoughness) trace the reflected ray and see the light the voxel it hits
// reflects, or an emitter's exact geometry where the ray meets one first (a light
// the size of its voxels would look too big); glossy surfaces trace one ray per
// frame towards a GGX micro-normal drawn from the visible normals (Heitz 2018) and
// see reflected light only (their highlight from the lights comes from the shadows
// stage). Weighted by Schlick's Fresnel. Dielectrics rougher than kGlossyRoughness
// are skipped.
//
// A glossy pixel whose mean holds fewer than kFewLobeSamples samples (the first
// frames after a restart, a camera move or a disocclusion) traces
// RTGI_FIRST_LOBE_RAYS rays in a frame (RtgiPass::Settings::firstLobeRays) and
// averages them: glossy surfaces are a few percent of the pixels, so the first
// frame costs little more, and their light, seen along one ray drawn from the lobe,
// was the noisiest of a first frame's (the hall's bronze knot at 1 frame, FLIP
// 0.305 with one ray, 0.239 with four). A mirror traces them only where its
// reflection is strongly minified: where the directions it reflects across one
// pixel spread kMinifiedMirror times as far as the camera's rays or more (the
// reflected ray's differential, from the neighbours' G-buffer: Igehy 1999, "Tracing
// ray differentials"), one ray shows one point of a patch of the scene the pixel
// covers, and its rays are spread over the pixel's footprint. On a ball that spread
// is about 2 / (its radius in pixels x the camera's spread), so this is a ball under
// about 9 pixels in radius at 256 pixels and 60 degrees (the hall's mirror ball at
// 1 frame, FLIP 0.294 with one ray, 0.205 with four) and the rims of larger ones: few
// pixels. The bulk of a large ball (dark_plane's, 16-49 times) and flat mirrors keep
// one ray: there the rays of every pixel cost dark_plane's first frame 85 ms (a
// quarter) for a FLIP 3% lower over the image
// (docs/measurements.md#2026-12-07-first-lobe-rays, #2026-12-07-mirror-footprint).
//
// RTGI_BVH (the effect plan has the specular effect and the Renderer built a BVH):
// the reflected ray finds its hit on the exact triangles (rtgi_bvh.glsl) instead,
// passes on through up to kMaxMirrorChain further mirrors, and is shaded there with
// exact direct light (rtgi_direct_light.glsl, the shadows stage's estimators, with
// shadow rays through the BVH) plus the voxels' light along one cosine ray from the
// hit (the indirect stage's estimate; RTGI_BVH_RAYS: that ray on the triangles too),
// when the plan has indirect light: voxels serve only as the light cache behind the
// hit. A mirror sees an emitter it hits; a
// glossy surface does not (its highlight comes from the shadows stage), unless
// RTGI_HIGHLIGHT_MIS: then it shares the highlights of triangle emitters with the
// shadows stage (rtgi_direct_light.glsl).
// RTGI_BVH_TEXTURES, _COLORS, _ALPHA: the material's textures, vertex colours and
// alpha masks at the hit, as the path tracer reads them (rtgi_bvh.glsl).
//
// RTGI_CONES (--indirect cones): a glossy surface reads one cone about the mirror
// direction through the octree's filtered levels, its aperture following the
// roughness (rtgi_cones.glsl), weighted by Schlick's Fresnel at the normal: the same
// light every frame instead of one ray's. Mirrors keep their ray.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "octree_light.glsl"
#define RTGI_PIXEL_LIST
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiTraceGroup) in;

layout(std430, binding = kOctreeRadianceBinding) readonly buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeMaterialBinding) readonly buffer Material { uvec2 material[]; };
layout(binding = kSpecularImage, rgba16f) uniform writeonly image2D specularOut;

#ifndef RTGI_FIRST_LOBE_RAYS
#define RTGI_FIRST_LOBE_RAYS 4
#endif
const int kFirstLobeRays = RTGI_FIRST_LOBE_RAYS;
const float kFewLobeSamples = 4.0;
const float kMinifiedMirror = 48.0;

#include "rtgi_sample_count.glsl"

#ifdef RTGI_CONES
#include "rtgi_cones.glsl"
#endif

#ifdef RTGI_BVH
#include "rtgi_bvh.glsl"

float shadowRay(vec3 o, vec3 l, float dist, bool toEmitter, float slack) {
  return bvhVisible(o, l, dist, toEmitter, slack);
}

#include "rtgi_direct_light.glsl"
#include "rtgi_hit.glsl"
#ifdef RTGI_BVH_RAYS
#include "rtgi_voxel_light.glsl"
#endif

// Radiance arriving at o from unit direction dir: the nearest triangle's (after up to
// kMaxMirrorChain mirrors) direct light, its voxel indirect light and, when
// `seeEmitters`, its emission. `share` (RTGI_HIGHLIGHT_MIS, a glossy pixel's lobe
// ray): the first hit's emission, where it is a triangle emitter, weighed by this
// ray's share of the highlight of `pixel` (rtgi_direct_light.glsl).
vec3 reflectedRadiance(vec3 o, vec3 dir, bool seeEmitters, bool share, Surface pixel) {
  loopBudget = kPtLoopBudget;
  float eps = bvhEpsilon();
  vec3 throughput = vec3(1.0);
  vec3 result = vec3(0.0);
  for (int bounce = 0; bounce <= kMaxMirrorChain; ++bounce) {
    TriangleHit h;
    if (!traceSurface(o, dir, h)) break;
    if (seeEmitters) result += throughput * h.emission;
#ifdef RTGI_HIGHLIGHT_MIS
    if (bounce == 0 && share && any(greaterThan(h.emission, vec3(0.0)))) {
      // A cluster's facets (negated pdf) are left to the light sample.
      GpuPtTriangle T = loadTriangle(h.tri);
      if (T.e1.w > 0.0) {
        float omega =
            triangleSolidAngle(T.v0.xyz, T.v0.xyz + T.e1.xyz, T.v0.xyz + T.e2.xyz, pixel.p);
        result += h.emission * (1.0 - highlightLightShare(pixel, dir, omega));
      }
    }
#endif
    if (h.roughness < kMirrorRoughness) {
      // A mirror: on along the reflection, weighted as the first (Schlick).
      if (bounce == kMaxMirrorChain) break;
      throughput *= schlickFresnel(h.s.f0, clamp(dot(h.s.n, -dir), 0.0, 1.0));
      dir = reflect(dir, h.s.n);
      if (dot(dir, h.ng) <= 0.0) break;
      o = h.s.p + h.ng * eps;
      continue;
    }
    vec3 p = h.s.p, ng = h.ng, ns = h.s.n, below = h.below;
    result += throughput * directLight(h.s, p + ng * eps, below);
    // The light the voxels send along one ray drawn from the hit's BSDF (the path
    // tracer's: its GGX lobe by visible normals, or the cosine, chosen by their
    // Fresnel weight), weighed by BSDF x cosine / pdf: a metal's lobe too, which a
    // cosine ray weighed by the Lambert part left black.
    if ((rtgi.flags & kRtgiHasIndirect) != 0u) {
      vec3 d;
      Bsdf bsdf = makeBsdf(h.base, h.metallic, h.roughness, clamp(dot(ns, -dir), 0.0, 1.0));
      if (sampleBsdf(bsdf, ns, -dir, rngState, d)) {
        float pdf;
        vec3 w = evalBsdf(bsdf, ns, -dir, d, pdf);
        w = pdf > 0.0 ? w / pdf : vec3(0.0);
#ifdef RTGI_BVH_RAYS
        // On the triangles too, as the indirect stage's rays (rtgi_voxel_light.glsl).
        if (dot(d, below) >= 0.0 && dot(d, ng) > 0.0)
          result += throughput * w * voxelLightAlong(p + ng * eps, d);
#else
        MarchHit m = octreeTrace(octreeWorldRay(rayOrigin(h.s), d, 3.0e38), 0.0, kRaySteps);
        uint word = m.hit ? material[m.node].y : 0u;
        if (m.hit && !seenFromBehind(word, d))
          result += throughput * w * unpackRgb9e5(radiance[lightSlot(m.node, word, -d)]);
#endif
      }
    }
    break;
  }
  return result;
}
#endif

// The direction a mirror pixel q reflects the camera's ray into, or 0 where q is not
// on a mirror facing the same way as `n` (another surface, an edge).
vec3 mirrorDirection(ivec2 q, vec3 n) {
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(rtgi.width, rtgi.height))))
    return vec3(0.0);
  vec4 pos = texelFetch(gPosition, q, 0);
  vec4 nr = texelFetch(gNormal, q, 0);
  if (pos.w < 0.5 || nr.w >= kMirrorRoughness) return vec3(0.0);
  vec3 nq = normalize(nr.xyz);
  if (dot(nq, n) < 0.5) return vec3(0.0);
  return reflect(normalize(pos.xyz - rtgi.camera.xyz), nq);
}

// How a mirror pixel's reflected direction r changes across the pixel along one
// image axis e (a ray differential, Igehy 1999, "Tracing ray differentials", taken
// from the neighbours' G-buffer): the central difference where both neighbours lie
// on the mirror, else the one-sided one, else 0.
vec3 mirrorDifferential(ivec2 px, ivec2 e, vec3 r, vec3 n) {
  vec3 a = mirrorDirection(px + e, n), b = mirrorDirection(px - e, n);
  if (a != vec3(0.0) && b != vec3(0.0)) return 0.5 * (a - b);
  if (a != vec3(0.0)) return a - r;
  if (b != vec3(0.0)) return r - b;
  return vec3(0.0);
}

// The light one ray brings along the pixel's reflection (a mirror: `footprint` turns
// it towards a point of the pixel, offsets in [-1/2, 1/2] along the differentials
// dx, dy) or drawn from its GGX lobe, weighted by BSDF x cosine / pdf.
vec3 lobeLight(Surface s, bool mirror, vec2 footprint, vec3 dx, vec3 dy) {
  vec3 dir;
  vec3 h = s.n;
  if (mirror) {
    dir = normalize(reflect(-s.v, s.n) + footprint.x * dx + footprint.y * dy);
  } else {
    vec3 t, bt;
    basis(s.n, t, bt);
    vec3 ve = vec3(dot(s.v, t), dot(s.v, bt), dot(s.v, s.n));
    vec3 m = sampleVndf(ve, max(s.alpha, 1e-3), vec2(rand01(), rand01()));
    h = normalize(t * m.x + bt * m.y + s.n * m.z);
    dir = reflect(-s.v, h);
  }
  if (dot(dir, s.n) > 0.0) {
    vec3 f = schlickFresnel(s.f0, clamp(dot(s.v, h), 0.0, 1.0));
    if (!mirror) {
      // The lobe ray's weight, BSDF x cosine / pdf, is F G2 / G1 (Heitz 2018), G2
      // the height-correlated masking-shadowing of the direct stage's highlights.
      float nv = max(dot(s.n, s.v), 1e-4), nl = dot(s.n, dir);
      float alpha = max(s.alpha, 1e-3);
      f *= 4.0 * nl * nv * smithVisibility(nl, nv, alpha) / smithG1(nv, alpha);
    }
#ifdef RTGI_BVH
    bool share = false;
#ifdef RTGI_HIGHLIGHT_MIS
    share = !mirror && (rtgi.flags & kRtgiHasDirect) != 0u;
#endif
    return f * reflectedRadiance(s.p + s.n * bvhEpsilon(), dir, mirror, share, s);
#else
    vec3 o = rayOrigin(s);
    MarchHit hit = octreeTrace(octreeWorldRay(o, dir, 3.0e38), 0.0, kRaySteps);
    uint word = hit.hit ? material[hit.node].y : 0u;
    vec3 l = hit.hit && !seenFromBehind(word, dir)
                 ? unpackRgb9e5(radiance[lightSlot(hit.node, word, -dir)])
                 : vec3(0.0);
    if (mirror) {
      // Lights seen in a mirror: the exact emitters, unless a voxel closer than
      // the emitter's own voxels (kSurfaceOffsetVoxels in front) hides them.
      float tVoxel = hit.hit ? (hit.t + 2.0 * kSurfaceOffsetVoxels) * octreeVoxelSize() : 3.0e38;
      vec3 e = emitterAlongRay(o, dir, tVoxel, int(rtgi.emitterCount));
      if (any(greaterThan(e, vec3(0.0)))) l = e;
    }
    return f * l;
#endif
  }
  return vec3(0.0);
}

void main() {
  ivec2 px;
  if (!tracePixel(px)) return;
  Pixel p = loadPixel(px);
  vec3 result = vec3(0.0);
  bool mirror = p.roughness < kMirrorRoughness;
  if (p.covered && (mirror || isSpecular(p.metallic, p.roughness))) {
#ifdef RTGI_CONES
    if (!mirror) {
      Surface s = p.s;
      vec3 dir = reflect(-s.v, s.n);
      vec3 f = schlickFresnel(s.f0, clamp(dot(s.v, s.n), 0.0, 1.0));
      if (dot(dir, s.n) > 0.0)
        result = f * coneRadiance(surfaceRayOrigin(px, s), dir, glossyConeHalfTan(s.alpha));
      imageStore(specularOut, px, vec4(result, 1.0));
      return;
    }
#endif
    seedPixel(px, 3u);
    // A glossy pixel with few samples yet traces kFirstLobeRays (above), and so does
    // a mirror whose reflection is strongly minified (the directions it reflects
    // across one pixel spread kMinifiedMirror times as far as the camera's rays
    // across it), its rays spread over the pixel's footprint.
    int rays = 1;
    vec3 dx = vec3(0.0), dy = vec3(0.0);
    bool few = kFirstLobeRays > 1 && samplesSoFar(px) < kFewLobeSamples;
    if (few && mirror) {
      vec3 r = reflect(-p.s.v, p.s.n);
      dx = mirrorDifferential(px, ivec2(1, 0), r, p.s.n);
      dy = mirrorDifferential(px, ivec2(0, 1), r, p.s.n);
      if (max(length(dx), length(dy)) > kMinifiedMirror * rtgi.pixelSpread) rays = kFirstLobeRays;
    } else if (few) {
      rays = kFirstLobeRays;
    }
    for (int i = 0; i < rays; ++i) {
      vec2 footprint = mirror && rays > 1 ? vec2(rand01(), rand01()) - 0.5 : vec2(0.0);
      result += lobeLight(p.s, mirror, footprint, dx, dy);
    }
    result /= float(rays);
  }
  imageStore(specularOut, px, vec4(result, 1.0));
}
