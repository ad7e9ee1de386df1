#version 450 core
// rtgi stage "denoise", first pass: each pixel's running mean of each term (the
// direct one, and the rest: the mean of all less it) divided by its base colour,
// with the variance of that mean's luminance in alpha, for the a-trous passes
// (rtgi_denoise.comp), and the key their edge stops compare. The variance of a mean
// of n samples is the samples' variance over n. A pixel with kDenoiseTemporalSamples
// samples or more takes its samples' variance from its own moments
// (rtgi_accumulate.comp); one with fewer (just after a restart or a disocclusion)
// from the 7x7 pixels around it: with two samples or more, the mean of their
// samples' variances; with one, the variance of their pooled moments (Schied et al.
// 2017, sec. 4.2), which counts the light's change from pixel to pixel as noise too.
// Pixels the filter keeps as they are (denoiseKeeps) get alpha -1.
//
// The window is a box, not SVGF's bilateral one: the variance only sets how far the
// a-trous passes' luminance stop lets light through, and their own edge stops
// (normal, depth, material) keep it on its surface. Weighted by the edge stops the
// estimate gave the same first frames (FLIP within 0.0003 on seven views of the
// validation set, two seeds; the hall's gallery 0.0008-0.0012 better with the box)
// and its 13 edge weights a pixel cost a third of the first frame's denoise stage.
//
// The 7x7 neighbourhood is read from shared memory: a group that has such a pixel
// first loads its tile and a 3-pixel border once (each pixel's sample count and
// moments), where each pixel fetching its 48 neighbours' texels took half the first
// frame's denoise stage. The 7x7 sums are taken in two 7-tap passes, along the
// tile's rows and then down its columns.
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
// Per tile pixel: the sample count (-1: not drawn, or outside the image), and the
// moments.
shared float tileSamples[kTile * kTile];
shared vec4 tileMoments[kTile * kTile];
// The row pass's sums at each pixel of the tile's rows below the group's columns
// (kTile rows of kDenoisePrepareGroup): the pooled moments in tileMoments' place,
// once the row pass has read them, and here the samples' variances with the two
// counts (rowSums).
const int kRows = kTile * int(kDenoisePrepareGroup);
shared vec4 rowVariance[kRows];
shared uint tileNeeded;

// The variance of the samples whose moments are m, n of them (n >= 2): unbiased.
vec2 samplesVariance(vec4 m, float n) {
  return max(m.yw - m.xz * m.xz, vec2(0.0)) * (n / (n - 1.0));
}

// The row pass at entry e of the tile's rows below the group's columns: the sums
// over its row's 7 pixels centred on it: the moments of those with a sample or more
// (pooled), then the variances of those with two or more and the two counts
// (variance: xy the variances, z the pooled moments' count, w the variances').
void rowSum(int e, out vec4 pooled, out vec4 variance) {
  pooled = vec4(0.0);
  variance = vec4(0.0);
  if (e >= kRows) return;
  int centre = (e / int(kDenoisePrepareGroup)) * kTile + e % int(kDenoisePrepareGroup) + 3;
  for (int dx = -3; dx <= 3; ++dx) {
    int i = centre + dx;
    float nq = tileSamples[i];
    if (!(nq >= 1.0)) continue;
    vec4 mq = tileMoments[i];
    pooled += mq;
    variance.z += 1.0;
    if (nq >= 2.0) variance += vec4(samplesVariance(mq, nq), 0.0, 1.0);
  }
}

// The row pass over the whole tile, two entries an invocation at most, written over
// the moments once all are read. (Two calls, not a loop over an array: a software
// rasterizer keeps an array indexed in a loop in memory, one lane at a time.)
void rowSums() {
  const int threads = int(kDenoisePrepareGroup * kDenoisePrepareGroup);
  int e = int(gl_LocalInvocationIndex);
  vec4 pooled0, variance0, pooled1, variance1;
  rowSum(e, pooled0, variance0);
  rowSum(e + threads, pooled1, variance1);
  barrier();
  tileMoments[e] = pooled0;
  rowVariance[e] = variance0;
  if (e + threads < kRows) {
    tileMoments[e + threads] = pooled1;
    rowVariance[e + threads] = variance1;
  }
  barrier();
}

// Loads the group's tile into shared memory when one of its pixels estimates its
// variance from its neighbours, and takes the row pass (rowSums). In uniform control
// flow: every invocation calls it.
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
    float samples = -1.0;
    vec4 m = vec4(0.0);
    if (all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size)) &&
        texelFetch(gPosition, q, 0).w >= 0.5) {
      samples = texelFetch(mean, q, 0).a;
      m = texelFetch(moments, q, 0);
    }
    tileSamples[i] = samples;
    tileMoments[i] = m;
  }
  barrier();
  rowSums();
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
    // Too few samples of its own: the moments of the pixels around it that have
    // samples. With two samples or more, each pixel's own samples' variance,
    // averaged: the light's change from pixel to pixel is not noise (the moments
    // pooled over the pixels would count a hard shadow's edge as noise, and the
    // filter would carry the light across it). With one, only the pooled moments tell
    // anything. The column pass: the row sums above and below.
    bool own = n >= 2.0;
    vec4 pooled = vec4(0.0);
    vec4 variance = vec4(0.0);  // xy: the samples' variances; z, w: the counts
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    for (int dy = -3; dy <= 3; ++dy) {
      int e = (local.y + 3 + dy) * int(kDenoisePrepareGroup) + local.x;
      pooled += tileMoments[e];
      variance += rowVariance[e];
    }
    if (own && variance.w > 0.0) {
      vec2 v = variance.xy / variance.w / n;
      imageStore(
          prepared, px,
          packDenoiseTerms(vec4(direct / albedo, v.x), vec4((c.rgb - direct) / albedo, v.y)));
      return;
    }
    if (variance.z > 0.0) m = pooled / variance.z;
  }
  vec2 variance = max(m.yw - m.xz * m.xz, vec2(0.0)) / max(n, 1.0);
  imageStore(prepared, px,
             packDenoiseTerms(vec4(direct / albedo, variance.x),
                              vec4((c.rgb - direct) / albedo, variance.y)));
}
