#version 450 core
// rtgi stage "denoise", first pass: each pixel's running mean of each term (the
// direct one, and the rest: the mean of all less it) divided by its base colour,
// with the variance of that mean's luminance in alpha, for the a-trous passes
// (rtgi_denoise.comp), and the key their edge stops compare. The variance of a mean
// of n samples is the samples' variance over n. A pixel with kDenoiseTemporalSamples
// samples or more takes its samples' variance from its own moments
// (rtgi_accumulate.comp); one with fewer (just after a restart or a disocclusion)
// from the 7x7 pixels around it on the same surface: with two samples or more, the
// mean of their samples' variances; with one, the variance of their pooled moments
// (Schied et al. 2017, sec. 4.2), which counts the light's change from pixel to
// pixel as noise too. Pixels the filter keeps as they are (denoiseKeeps) get alpha -1.
//
// The 7x7 neighbourhood is read from shared memory: a group that has such a pixel
// first loads its tile and a 3-pixel border once (what each neighbour's weight
// needs: position, normal, material, sample count, moments), where each pixel
// fetching its 48 neighbours' texels took half the first frame's denoise stage.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "rtgi_common.glsl"
#include "rtgi_denoise.glsl"

layout(local_size_x = kDenoisePrepareGroup, local_size_y = kDenoisePrepareGroup) in;

layout(binding = kHistoryUnit) uniform sampler2D mean;  // the accumulation target
layout(binding = kHistoryMomentsUnit) uniform sampler2D moments;
layout(binding = kHistoryDirectUnit) uniform sampler2D directMean;
layout(binding = kDenoiseOutImage, rgba32ui) uniform writeonly uimage2D prepared;
layout(binding = kDenoiseKeyImage, rgba32ui) uniform writeonly uimage2D keys;

const int kTile = int(kDenoisePrepareGroup) + 6;  // the group and its 3-pixel border
// Per tile pixel: position and sample count (-1: not drawn, or outside the image),
// normal and material, moments.
shared vec4 tilePosition[kTile * kTile];
shared vec4 tileNormal[kTile * kTile];
shared vec4 tileMoments[kTile * kTile];
shared uint tileNeeded;

DenoiseKey keyAt(ivec2 px) {
  DenoiseKey k;
  vec4 p = texelFetch(gPosition, px, 0);
  k.position = p.xyz;
  k.normal = denoiseNormal(px);
  k.material = uint(p.w) & 1023u;
  return k;
}

// Loads the group's tile into shared memory when one of its pixels estimates its
// variance from its neighbours. In uniform control flow: every invocation calls it.
void loadTile(ivec2 size, bool needed) {
  if (gl_LocalInvocationIndex == 0u) tileNeeded = 0u;
  barrier();
  if (needed) atomicOr(tileNeeded, 1u);
  barrier();
  if (tileNeeded == 0u) return;
  ivec2 origin = ivec2(gl_WorkGroupID.xy * kDenoisePrepareGroup) - 3;
  uint threads = kDenoisePrepareGroup * kDenoisePrepareGroup;
  for (uint i = gl_LocalInvocationIndex; i < uint(kTile * kTile); i += threads) {
    ivec2 q = origin + ivec2(int(i) % kTile, int(i) / kTile);
    vec4 position = vec4(0.0, 0.0, 0.0, -1.0);
    vec4 normal = vec4(0.0);
    vec4 m = vec4(0.0);
    if (all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size))) {
      vec4 p = texelFetch(gPosition, q, 0);
      if (p.w >= 0.5) {
        position = vec4(p.xyz, texelFetch(mean, q, 0).a);
        normal = vec4(normalize(texelFetch(gNormal, q, 0).xyz), p.w);
        m = texelFetch(moments, q, 0);
      }
    }
    tilePosition[i] = position;
    tileNormal[i] = normal;
    tileMoments[i] = m;
  }
  barrier();
}

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(rtgi.width, rtgi.height);
  bool inside = px.x < size.x && px.y < size.y;
  vec4 c = inside ? texelFetch(mean, px, 0) : vec4(0.0);
  bool keeps = !inside || denoiseKeeps(px);
  loadTile(size, !keeps && c.a < kDenoiseTemporalSamples);
  if (!inside) return;
  if (keeps) {
    imageStore(prepared, px, packDenoiseTerms(vec4(c.rgb, -1.0), vec4(0.0, 0.0, 0.0, -1.0)));
    return;
  }
  vec4 position = texelFetch(gPosition, px, 0);
  imageStore(keys, px, packDenoiseKey(position, denoiseNormal(px)));
  vec4 directAndAlbedo = texelFetch(directMean, px, 0);
  vec3 albedo = denoiseAlbedo(px, directAndAlbedo.a);
  vec3 direct = directAndAlbedo.rgb;
  float n = c.a;
  vec4 m = texelFetch(moments, px, 0);
  if (n < kDenoiseTemporalSamples) {
    // Too few samples of its own: the moments of the pixels around it on its surface
    // that have samples.
    DenoiseKey p = keyAt(px);
    float scale = rtgi.denoisePlane * length(p.position - rtgi.camera.xyz) + 1e-6;
    // With two samples or more, each pixel's own samples' variance, averaged: the
    // light's change from pixel to pixel is not noise (the moments pooled over the
    // pixels would count a hard shadow's edge as noise, and the filter would carry
    // the light across it). With one, only the pooled moments tell anything.
    bool own = n >= 2.0;
    vec4 sum = n > 0.0 ? m : vec4(0.0);
    vec2 within = own ? max(m.yw - m.xz * m.xz, vec2(0.0)) * (n / (n - 1.0)) : vec2(0.0);
    float weight = n > 0.0 ? 1.0 : 0.0;
    ivec2 local = ivec2(gl_LocalInvocationID.xy) + 3;
    for (int dy = -3; dy <= 3; ++dy)
      for (int dx = -3; dx <= 3; ++dx) {
        int i = (local.y + dy) * kTile + local.x + dx;
        vec4 position = tilePosition[i];
        float nq = position.w;  // -1 outside the image or where nothing is drawn
        if ((dx == 0 && dy == 0) || !(nq >= (own ? 2.0 : 1.0))) continue;
        DenoiseKey q;
        q.position = position.xyz;
        q.normal = tileNormal[i].xyz;
        q.material = uint(tileNormal[i].w) & 1023u;
        float w = exp(logEdgeWeight(p, q, scale));
        vec4 mq = tileMoments[i];
        sum += w * mq;
        within += w * max(mq.yw - mq.xz * mq.xz, vec2(0.0)) * (nq / (nq - 1.0));
        weight += w;
      }
    if (weight > 0.0) m = sum / weight;
    if (own && weight > 0.0) {
      vec2 variance = within / weight / n;
      imageStore(prepared, px,
                 packDenoiseTerms(vec4(direct / albedo, variance.x),
                                  vec4((c.rgb - direct) / albedo, variance.y)));
      return;
    }
  }
  vec2 variance = max(m.yw - m.xz * m.xz, vec2(0.0)) / max(n, 1.0);
  imageStore(prepared, px,
             packDenoiseTerms(vec4(direct / albedo, variance.x),
                              vec4((c.rgb - direct) / albedo, variance.y)));
}
