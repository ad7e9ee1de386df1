#version 450 core
// rtgi stage "caustics": light that reaches a surface the camera sees only by way of
// mirrors (the paths light -> mirror(s) -> surface -> camera), which no other stage
// estimates: a pixel's indirect ray that meets a mirror keeps the mirror's diffuse
// part only, and its shadow rays see the mirror as an occluder. Light tracing
// (particle tracing, Veach 1997, "Robust Monte Carlo methods for light transport
// simulation", ch. 10; the t = 1 strategy of bidirectional path tracing): each
// invocation sends one photon from an emissive surface, aimed at a mirror, along its
// reflections (up to kMaxMirrorChain mirrors) to the first other surface it meets,
// and connects that point to the camera with a visibility ray through the BVH. The
// photon's contribution lands in the pixel its point projects to; per pixel the sum
// over the frame's photons, divided by their count, is an unbiased estimate of the
// caustic light averaged over the pixel (a box, as the jittered samples of the other
// stages average it), which accumulate adds to the pixel's sample. A tent over the
// four nearest pixels spread a caustic onto the surfaces beside it, an emitter's
// pixels included.
//
// Photons are aimed (Jensen 1996, "Global illumination using photon maps": the
// projection map): a mirror's direction is drawn uniformly inside the cone its
// bounding sphere subtends from the photon's origin (the spheres: RtgiPass, one per
// run of triangles drawn with a mirror material, kMaxCausticTargets at most), and
// weighed by the mixture's pdf over every sphere whose cone holds it, so a path is
// counted once whichever sphere drew it. Every path the stage must count leaves the
// emitter towards a mirror, so inside one of the cones: aiming drops none. A photon
// whose first surface is not a mirror stops (direct light carries that path).
//
// Punctual lights send no photons: through a mirror their light reaches a point
// from one direction only, which neither a path tracer nor the reference images can
// find, so leaving them out keeps rtgi comparable with them
// (docs/rtgi.md#caustics).
//
// Each photon adds its light to three 64-bit fixed-point numbers per pixel with
// 32-bit integer atomics (GL 4.5 has no float atomics, llvmpipe no 64-bit ones):
// float additions would round in the order the threads come, and the image would
// differ from run to run.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "octree_light.glsl"
#include "rtgi_common.glsl"
#include "rtgi_bvh.glsl"
#include "rtgi_hit.glsl"

layout(local_size_x = kRtgiTraceGroup) in;

layout(std140, binding = kFrameBinding) uniform FrameBlock { GpuFrame frame; };
// Each mirror's bounding sphere: xyz its centre, w its radius.
layout(std430, binding = kRtgiCausticTargetBinding) readonly buffer Targets { vec4 targets[]; };
// Per pixel of the internal image, rgb in 32.32 fixed point (atomicAddFixed; RtgiPass
// clears it each frame).
layout(std430, binding = kRtgiCausticBinding) buffer Caustic { uint caustic[]; };

// Adds v >= 0 to the fixed-point number at caustic[i] (the low word, 32 bits of
// fraction) and caustic[i + 1] (the high word, the integer part): integer additions,
// with the low word's carry, so the sum is the same in whatever order the photons
// add, and the image is the same every run.
void atomicAddFixed(uint i, float v) {
  uint lo = uint(fract(v) * 4294967296.0);
  uint old = atomicAdd(caustic[i], lo);
  uint hi = uint(floor(v)) + (old + lo < old ? 1u : 0u);
  if (hi != 0u) atomicAdd(caustic[i + 1u], hi);
}

void splat(ivec2 q, vec3 c) {
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(rtgi.width, rtgi.height))))
    return;
  uint i = 6u * (uint(q.y) * rtgi.width + uint(q.x));
  atomicAddFixed(i, c.r);
  atomicAddFixed(i + 2u, c.g);
  atomicAddFixed(i + 4u, c.b);
}

// The cosine of the half-angle of the cone sphere t subtends from o (-1: o is inside
// it, the whole sphere of directions), and the cone's axis.
float targetCone(vec4 t, vec3 o, out vec3 axis) {
  vec3 d = t.xyz - o;
  float d2 = dot(d, d);
  axis = d2 > 0.0 ? d * inversesqrt(d2) : vec3(0.0, 1.0, 0.0);
  if (d2 <= t.w * t.w) return -1.0;
  return sqrt(max(1.0 - t.w * t.w / d2, 0.0));
}

// The solid-angle pdf of direction w under the mixture of the targets' cones, each
// drawn with probability 1 / count.
float aimPdf(vec3 o, vec3 w, uint count) {
  float pdf = 0.0;
  for (uint k = 0u; k < count; ++k) {
    vec3 axis;
    float cosMax = targetCone(targets[k], o, axis);
    if (dot(w, axis) >= cosMax) pdf += 1.0 / (2.0 * kPi * (1.0 - cosMax));
  }
  return pdf / float(count);
}

void main() {
  uint photon = gl_GlobalInvocationID.x;
  uint photons = rtgi.causticPhotons;
  uint targetCount = rtgi.causticTargets;
  if (photon >= photons || targetCount == 0u || rtgi.emitterCount == 0u) return;
  rngState = pcgHash(pcgHash(pcgHash(rtgi.seed + 9u * 0x9e3779b9u) + photon) + rtgi.frameIndex);

  // The emitter, by power, a point on it, and a direction aimed at one mirror.
  float pmf;
  int k = pickEmitter(rand01(), int(rtgi.emitterCount), pmf);
  GpuEmitter e = emitters[k];
  vec3 y = emitterPoint(e, vec2(rand01(), rand01()));
  vec3 ne = e.kind == kEmitterCluster ? e.b : cross(e.b - e.a, e.c - e.a);
  float area = e.kind == kEmitterCluster ? e.area : 0.5 * length(ne);
  ne = normalize(ne);
  uint t = min(uint(rand01() * float(targetCount)), targetCount - 1u);
  vec3 axis;
  float cosMax = targetCone(targets[t], y, axis);
  float cosTheta = 1.0 - rand01() * (1.0 - cosMax);
  float sinTheta = sqrt(max(1.0 - cosTheta * cosTheta, 0.0));
  float phi = 2.0 * kPi * rand01();
  vec3 tu, tv;
  basis(axis, tu, tv);
  vec3 dir = normalize(axis * cosTheta + sinTheta * (cos(phi) * tu + sin(phi) * tv));
  float cosE = dot(ne, dir);
  if (e.twoSided != 0u) cosE = abs(cosE);
  float pdfDir = aimPdf(y, dir, targetCount);
  if (!(cosE > 0.0) || !(pdfDir > 0.0) || !(pmf > 0.0)) return;
  // Power / pdf: radiance x cosine x area over the emitter's, the point's and the
  // direction's probabilities.
  vec3 beta = e.radiance * (cosE * area / (pmf * pdfDir));

  loopBudget = kPtLoopBudget;
  float eps = bvhEpsilon();
  vec3 o = y + (dot(ne, dir) > 0.0 ? ne : -ne) * eps;
  for (int bounce = 0; bounce <= kMaxMirrorChain; ++bounce) {
    TriangleHit h;
    if (!traceSurface(o, dir, h)) return;
    if (h.roughness < kMirrorRoughness) {
      if (bounce == kMaxMirrorChain) return;
      beta *= schlickFresnel(h.s.f0, clamp(dot(h.s.n, -dir), 0.0, 1.0));
      dir = reflect(dir, h.s.n);
      if (dot(dir, h.ng) <= 0.0) return;
      o = h.s.p + h.ng * eps;
      continue;
    }
    if (bounce == 0) return;  // no mirror on the way: direct light's path
    // Connect the surface to the camera: the pixel it projects to, and whether the
    // camera sees it.
    vec3 p = h.s.p;
    vec3 toCam = rtgi.camera.xyz - p;
    float dist = length(toCam);
    vec3 wc = toCam / dist;
    if (dot(wc, h.ng) <= 0.0 || (h.below != vec3(0.0) && dot(wc, h.below) <= 0.0)) return;
    vec4 clip = mat4(frame.viewProj[0], frame.viewProj[1], frame.viewProj[2], frame.viewProj[3]) *
                vec4(p, 1.0);
    if (!(clip.w > 0.0)) return;
    vec2 at = (clip.xy / clip.w * 0.5 + 0.5) * vec2(rtgi.width, rtgi.height) - 0.5;
    if (any(lessThan(at, vec2(-1.0))) || any(greaterThan(at, vec2(rtgi.width, rtgi.height))))
      return;
    float cosCam = dot(-wc, rtgi.cameraForward.xyz);
    if (!(cosCam > 0.0)) return;
    if (bvhVisible(p + h.ng * eps, wc, dist, false, 0.0) == 0.0) return;
    // BSDF x cosine towards the camera, by reciprocity with the photon's direction as
    // the view; then the pinhole's importance: 1 / (pixel area on the image plane at
    // distance 1 x cos^3 at the camera x distance^2) (Veach 1997, 10.3).
    float pdf;
    Bsdf b = makeBsdf(h.base, h.metallic, h.roughness, clamp(dot(h.s.n, -dir), 0.0, 1.0));
    vec3 f = evalBsdf(b, h.s.n, -dir, wc, pdf);
    float pixelArea = rtgi.pixelSpread * rtgi.pixelSpread;
    vec3 c = beta * f / (pixelArea * cosCam * cosCam * cosCam * dist * dist * float(photons));
    if (!all(lessThan(c, vec3(1.0e9))) || !all(greaterThanEqual(c, vec3(0.0)))) return;
    splat(ivec2(floor(at + 0.5)), c);
    return;
  }
}
