#version 450 core
// rtgi stage "accumulate": emission + direct + indirect + specular of this frame,
// averaged with the frames before it while camera and scene stay still (a running
// mean in float: the n-th sample of a pixel adds (c - mean) / n; alpha holds n).
// Pixels that traced nothing this frame (interleaving) keep their mean; with a sparse
// start, those that have not traced yet borrow their neighbours' light. A
// non-finite term is dropped rather than poisoning the mean, and counted
// (nonfinite.glsl). VOXGI_NO_EMISSION
// (effect plan) leaves emission out; RTGI_SPARSE_START (RtgiPass::Settings::sparseStart)
// adds the light lent to pixels that have not traced yet; RTGI_REPROJECTED, on a
// frame after a camera move, starts from the reproject stage's mean; RTGI_MOMENTS
// (the denoiser) keeps the mean of the direct term and the moments of each term's
// samples beside the mean;
// RTGI_RELIGHT, on a frame after meshes moved, drops the history of a pixel whose
// light has changed (historyStale). RTGI_CAUSTICS: the caustics stage ran
// (rtgi_caustics.comp); its light joins the traced light.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#define RTGI_TRACED_IMAGE
#include "rtgi_common.glsl"
#include "rtgi_denoise.glsl"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;

layout(binding = kDirectImage, rgba16f) uniform readonly image2D directIn;
layout(binding = kIndirectImage, rgba16f) uniform readonly image2D indirectIn;
layout(binding = kSpecularImage, rgba16f) uniform readonly image2D specularIn;
layout(binding = kAccumImage, rgba32f) uniform image2D accum;
#ifdef RTGI_CAUSTICS
// Per pixel, rgb in 32.32 fixed point (low word, high word: rtgi_caustics.comp).
layout(std430, binding = kRtgiCausticBinding) readonly buffer Caustic { uvec2 caustic[]; };

float causticChannel(uint i) {
  uvec2 v = caustic[i];
  return float(v.y) + float(v.x) * (1.0 / 4294967296.0);
}
#endif
#ifdef RTGI_REPROJECTED
layout(binding = kReprojectedImage, rgba32f) uniform readonly image2D reprojected;
#endif
#ifdef RTGI_MOMENTS
// The denoiser filters two terms apart (rtgi_denoise.glsl): the light straight from
// the lights (the direct stage's) and the rest (indirect and specular). Beside the
// mean of all, the running mean of the direct term, and the running means of each
// term's (luminance, luminance^2) divided by the base colour, over the same samples.
layout(binding = kMomentsImage, rgba32f) uniform image2D moments;
layout(binding = kDirectMeanImage, rgba32f) uniform image2D directMean;
#ifdef RTGI_REPROJECTED
layout(binding = kReprojectedMomentsUnit) uniform sampler2D reprojectedMoments;
layout(binding = kReprojectedDirectUnit) uniform sampler2D reprojectedDirect;
#endif

vec4 previousMoments(ivec2 px) {
#ifdef RTGI_REPROJECTED
  return texelFetch(reprojectedMoments, px, 0);
#else
  return rtgi.frameIndex > 0u ? imageLoad(moments, px) : vec4(0.0);
#endif
}

// The direct term's mean so far, and in alpha the base colour's (packAlbedoMean;
// 0 after a camera move: reproject starts it again).
vec4 previousDirect(ivec2 px) {
#ifdef RTGI_REPROJECTED
  return texelFetch(reprojectedDirect, px, 0);
#else
  return rtgi.frameIndex > 0u ? imageLoad(directMean, px) : vec4(0.0);
#endif
}

void storeTerms(ivec2 px, vec4 direct, vec4 m) {
  imageStore(directMean, px, direct);
  imageStore(moments, px, m);
}
#endif

// The mean so far: the target's, or on a frame after a camera move what the
// reproject stage made of it; none on the first frame.
vec4 previousMean(ivec2 px) {
#ifdef RTGI_REPROJECTED
  return imageLoad(reprojected, px);
#else
  return rtgi.frameIndex > 0u ? imageLoad(accum, px) : vec4(0.0);
#endif
}

// This frame's traced light (direct + indirect + specular) at pixel q, and its
// direct term alone.
vec3 tracedLight(ivec2 q, out vec3 direct) {
  vec3 c = vec3(0.0);
  uint flags = rtgi.flags;
  direct = (flags & kRtgiHasDirect) != 0u ? finiteOrZero(imageLoad(directIn, q).rgb) : vec3(0.0);
  if ((flags & kRtgiHasIndirect) != 0u) c += finiteOrZero(imageLoad(indirectIn, q).rgb);
  if ((flags & kRtgiHasSpecular) != 0u) c += finiteOrZero(imageLoad(specularIn, q).rgb);
#ifdef RTGI_CAUSTICS
  uint i = 3u * (uint(q.y) * rtgi.width + uint(q.x));
  c += vec3(causticChannel(i), causticChannel(i + 1u), causticChannel(i + 2u));
#endif
  return direct + c;
}

vec3 tracedLight(ivec2 q) {
  vec3 direct;
  return tracedLight(q, direct);
}

#ifdef RTGI_SPARSE_START
// A sparse start: light for a pixel that has not traced since the accumulation
// restarted, from the pixels around it that traced this frame. The pattern's turn
// puts one such pixel in every 4x4 block (the cell of turnRank()); the four of them
// around px are blended with bilinear weights, counting only those on px's surface
// (covered alike, normals within 25 degrees, depth within 5%), or, when none is,
// every covered one. `direct`: the direct term of what it returns.
vec3 borrowedLight(ivec2 px, out vec3 direct) {
  ivec2 size = ivec2(rtgi.width, rtgi.height);
  uint cell = interleaveCell(turnRank());
  ivec2 c = ivec2(cell & 3u, cell >> 2u);
  ivec2 block0 = (px - c) >> 2;  // the block whose traced pixel is at or before px
  vec2 t = vec2(px - (block0 * 4 + c)) / 4.0;
  vec4 p0 = texelFetch(gPosition, px, 0);
  vec3 n0 = texelFetch(gNormal, px, 0).xyz;
  float d0 = length(p0.xyz - rtgi.camera.xyz);
  vec3 same = vec3(0.0), near = vec3(0.0), sameDirect = vec3(0.0), nearDirect = vec3(0.0);
  float wSame = 0.0, wNear = 0.0;
  for (int k = 0; k < 4; ++k) {
    ivec2 b = block0 + ivec2(k & 1, k >> 1);
    ivec2 q = b * 4 + c;
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
    float w = ((k & 1) != 0 ? t.x : 1.0 - t.x) * ((k >> 1) != 0 ? t.y : 1.0 - t.y) + 1e-4;
    vec4 p1 = texelFetch(gPosition, q, 0);
    if (p1.w < 0.5) continue;  // nothing drawn there: no light traced
    vec3 lightDirect;
    vec3 light = tracedLight(q, lightDirect);
    vec3 n1 = texelFetch(gNormal, q, 0).xyz;
    float d1 = length(p1.xyz - rtgi.camera.xyz);
    near += w * light;
    nearDirect += w * lightDirect;
    wNear += w;
    if (sameSurface(p0.w > 0.5, n0, d0, true, n1, d1)) {
      same += w * light;
      sameDirect += w * lightDirect;
      wSame += w;
    }
  }
  if (wSame > 0.0) {
    direct = sameDirect / wSame;
    return same / wSame;
  }
  direct = wNear > 0.0 ? nearDirect / wNear : vec3(0.0);
  return wNear > 0.0 ? near / wNear : vec3(0.0);
}
#endif

#ifdef RTGI_RELIGHT
// After meshes moved, the light they send and block around them (shadows, bounced
// light) has changed on surfaces that keep their history, as no disocclusion test
// can see. A pixel's history is stale when it disagrees with this frame's light on
// the same surface around it by more than the noise of both allows: the luminance of
// light over base colour, its mean and variance over the pixels of the 5x5 block
// that traced this frame and show the pixel's material, normal and depth. The
// history is then dropped rather than clamped: a restart costs noise, which
// accumulation removes, where a clamp against a noisy neighbourhood would bias the
// mean for good.
const float kStaleSigmas = 4.0;  // how far beyond the noise, in standard deviations
const float kStaleSlack = 0.25;  // and relative to the light: its spatial variation

float relitLuminance(ivec2 q) {
#ifdef VOXGI_NO_EMISSION
  vec3 c = vec3(0.0);
#else
  vec3 c = finiteOrZero(texelFetch(gEmission, q, 0).rgb);
#endif
  return luminance((c + tracedLight(q)) / demodulation(q));
}

bool historyStale(ivec2 px, vec4 previous) {
  vec4 p0 = texelFetch(gPosition, px, 0);
  if (p0.w < 0.5) return false;
  vec3 n0 = texelFetch(gNormal, px, 0).xyz;
  float d0 = length(p0.xyz - rtgi.camera.xyz);
  float s1 = 0.0, s2 = 0.0, n = 0.0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      ivec2 q = px + ivec2(dx, dy);
      if (any(lessThan(q, ivec2(0))) || outside(q)) continue;
      vec4 p1 = texelFetch(gPosition, q, 0);
      if (p1.w != p0.w || !sameSurface(true, n0, d0, true, texelFetch(gNormal, q, 0).xyz,
                                       length(p1.xyz - rtgi.camera.xyz)))
        continue;
      float l = relitLuminance(q);
      s1 += l;
      s2 += l * l;
      n += 1.0;
    }
  if (n < 4.0) return false;  // too few to judge by
  float mean = s1 / n;
  float variance = max(s2 / n - mean * mean, 0.0) * n / (n - 1.0);
  float h = luminance(previous.rgb / demodulation(px));
  // The noise of the block's mean and of the history's, n and previous.a samples.
  float tolerance =
      kStaleSigmas * sqrt(variance / n + variance / previous.a) + kStaleSlack * max(mean, h);
  return abs(h - mean) > tolerance;
}
#endif

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (px.x >= int(rtgi.width) || px.y >= int(rtgi.height)) return;
  bool traced = !outside(px);
  vec4 previous = previousMean(px);
#ifndef RTGI_SPARSE_START
  bool keep = !traced;  // traced nothing this frame: it keeps its mean
#else
  // Until a pixel first traces it shows borrowed light with a count of 0, which its
  // first sample replaces; after that, untraced, it keeps its mean.
  bool keep = !traced && previous.a > 0.0;
#endif
  if (keep) {
#ifdef RTGI_REPROJECTED
    imageStore(accum, px, previous);
#ifdef RTGI_MOMENTS
    storeTerms(px, previousDirect(px), previousMoments(px));
#endif
#endif
    return;
  }
#ifdef VOXGI_NO_EMISSION
  vec3 c = vec3(0.0);
#else
  vec3 c = finiteOrZero(texelFetch(gEmission, px, 0).rgb);
#endif
#ifdef RTGI_SPARSE_START
  if (!traced) {
    bool covered = texelFetch(gPosition, px, 0).w > 0.5;
    vec3 direct = vec3(0.0);
    imageStore(accum, px, vec4(c + (covered ? borrowedLight(px, direct) : vec3(0.0)), 0.0));
#ifdef RTGI_MOMENTS
    storeTerms(px, vec4(direct, 0.0), vec4(0.0));
#endif
    return;
  }
#endif
  bool stale = false;
#ifdef RTGI_RELIGHT
  stale = previous.a > 0.0 && historyStale(px, previous);
  if (stale) previous = vec4(0.0);
#endif
  vec3 direct;
  vec3 light = tracedLight(px, direct);
  c += light;
  float n = previous.a + 1.0;
  vec3 mean = previous.rgb + (c - previous.rgb) / n;
  imageStore(accum, px, vec4(mean, n));
#ifdef RTGI_MOMENTS
  vec3 albedo = demodulation(px);
  float ld = luminance(direct / albedo), lr = luminance((light - direct) / albedo);
  vec4 m = stale ? vec4(0.0) : previousMoments(px);
  vec4 d = stale ? vec4(0.0) : previousDirect(px);
  // The base colour's mean over the same samples (rtgi_denoise.glsl).
  vec3 base = texelFetch(gAlbedo, px, 0).rgb;
  vec3 a = d.a > 0.0 ? mix(unpackAlbedoMean(d.a), base, 1.0 / n) : base;
  storeTerms(px, vec4(d.rgb + (direct - d.rgb) / n, packAlbedoMean(a)),
             m + (vec4(ld, ld * ld, lr, lr * lr) - m) / n);
#endif
}
