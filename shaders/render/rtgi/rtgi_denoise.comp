#version 450 core
// rtgi stage "denoise", the a-trous passes (Dammertz et al. 2010, as SVGF uses it:
// Schied et al. 2017, sec. 4.3): a 3x3 B-spline kernel whose taps lie
// denoisePass.x pixels apart, each weighted by the edge stops (rtgi_denoise.glsl)
// and by how far its luminance lies from the pixel's, against the noise of the
// noisier of the two (the square root of its variance); light moves between two
// pixels by the same weight both ways, so the filter keeps the image's light
// (exchange). The variance is filtered along with the light, by the squared
// weights. Each pass filters both terms (the direct light, and the rest:
// rtgi_denoise_prepare.comp), with the same edge stops but each against its own
// noise, so the sharp shadows of the direct light keep their edges where the noisier
// indirect light is smoothed. The last pass (denoisePass.y = 1) adds the two terms,
// multiplies them by the base colour again and writes the image shown; pixels the
// filter keeps (alpha < 0) show their mean. SVGF's 5x5 kernel over 5 passes reads
// 125 taps a pixel: here a 3x3 kernel over 5 passes spans as far (62 pixels) with 45
// taps.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "rtgi_common.glsl"
#include "rtgi_denoise.glsl"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;
layout(location = kDenoisePassLocation) uniform vec2 denoisePass;  // spacing, last

layout(binding = kDenoiseInImage, rgba32ui) uniform readonly uimage2D source;
layout(binding = kDenoiseOutImage, rgba32ui) uniform writeonly uimage2D filtered;
layout(binding = kDenoisedImage, rgba32f) uniform writeonly image2D denoised;
layout(binding = kDenoiseKeyImage, rgba32ui) uniform readonly uimage2D keys;
layout(binding = kHistoryUnit) uniform sampler2D mean;  // the accumulation target
// The direct term's mean: its alpha holds the base colour's (rtgi_denoise.glsl).
layout(binding = kHistoryDirectUnit) uniform sampler2D directMean;

const float kKernel[2] = float[2](1.0 / 2.0, 1.0 / 4.0);

float kernel(int k) { return kKernel[abs(k % 3 - 1)] * kKernel[abs(k / 3 - 1)]; }

// What one term of a pixel takes from one of its taps: `light` gathers the light
// (rgb) and the share of its own light the pixel keeps (alpha, from 1), `variance`
// the taps' part of the result's variance. c: the pixel's term, cq: the tap's (alpha:
// the variance of its luminance), logEdge: the log of the tap's edge stops, kernel:
// its kernel weight; `direct`: the direct light's term.
//
// Written as an exchange between pixels, not as a normalised average: the pixel
// keeps its light and takes w_pq (L_q - L_p) from each tap q, w_pq the kernel (the
// off-centre taps' 3/4 scaled to 1) times the edge stops times the luminance stop,
// which compares the two luminances against a noise both pixels agree on, so that
// w_pq = w_qp: what p takes from q, q gives to p, and the filter moves light without
// making or losing any, as a diffusion step does. The weights sum to at most 1 off
// the centre, so none is negative. The noise is the noisier pixel's for the indirect
// term, which has no edges of its own to keep; for the direct light the quieter
// pixel's, so a shadow's edge, exact on one side, is kept. A normalised average
// (SVGF's) is not symmetric: a pixel that drew a rare bright sample finds its
// neighbours far from it and keeps its light, while each darker neighbour finds it
// far from them and leaves it out, so the light of rare samples vanished: the
// filtered image was darker than the mean it filtered by 5.6% in the hall gallery
// after one frame and 2.2% after 16, by 12.6% and 3.1% in the sealed room; now by
// 0.07% at most.
//
// The taps are taken one at a time, with nothing kept in arrays: a software
// rasterizer keeps a local array indexed in a loop in memory, one lane at a time,
// and the 3x3 taps held in arrays made each pass twice as slow.
void exchange(vec4 c, vec4 cq, float logEdge, float kernel, bool direct, inout vec4 light,
              inout float variance) {
  float v = direct ? min(c.a, cq.a) : max(c.a, cq.a);
  if (!(v > 0.0)) return;  // no noise on either side: nothing to exchange
  float noise = rtgi.denoiseLuminance * sqrt(v) + 1e-6;
  float w = kernel * exp(logEdge - abs(luminance(cq.rgb) - luminance(c.rgb)) / noise);
  light += vec4(w * (cq.rgb - c.rgb), -w);
  variance += w * w * cq.a;
}

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(rtgi.width, rtgi.height);
  if (px.x >= size.x || px.y >= size.y) return;
  bool last = denoisePass.y > 0.5;
  uvec4 terms = imageLoad(source, px);
  vec4 c, c2;
  unpackDenoiseTerms(terms, c, c2);
  if (c.a < 0.0) {
    if (last) {
      imageStore(denoised, px, texelFetch(mean, px, 0));
    } else {
      imageStore(filtered, px, terms);
    }
    return;
  }
  int step = int(denoisePass.x);
  DenoiseKey p = unpackDenoiseKey(imageLoad(keys, px));
  float scale = rtgi.denoisePlane * length(p.position - rtgi.camera.xyz) + 1e-6;
  vec4 light = vec4(c.rgb, 1.0), light2 = vec4(c2.rgb, 1.0);
  float variance = 0.0, variance2 = 0.0;
  for (int k = 0; k < 9; ++k) {
    ivec2 q = px + (ivec2(k % 3, k / 3) - 1) * step;
    if (k == 4 || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
    vec4 cq, cq2;
    unpackDenoiseTerms(imageLoad(source, q), cq, cq2);
    if (cq.a < 0.0) continue;  // kept: both terms are
    float logEdge = logEdgeWeight(p, unpackDenoiseKey(imageLoad(keys, q)), scale);
    float w = (4.0 / 3.0) * kernel(k);
    exchange(c, cq, logEdge, w, true, light, variance);
    exchange(c2, cq2, logEdge, w, false, light2, variance2);
  }
  // The pixel's own variance counts by the square of the share of its light it kept.
  vec4 out1 = vec4(light.rgb, variance + light.a * light.a * c.a);
  vec4 out2 = vec4(light2.rgb, variance2 + light2.a * light2.a * c2.a);
  if (last) {
    imageStore(denoised, px,
               vec4((out1.rgb + out2.rgb) * denoiseAlbedo(px, texelFetch(directMean, px, 0).a),
                    texelFetch(mean, px, 0).a));
  } else {
    imageStore(filtered, px, packDenoiseTerms(out1, out2));
  }
}
