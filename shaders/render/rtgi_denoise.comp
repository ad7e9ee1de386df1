#version 450 core
// rtgi stage "denoise", the a-trous passes (Dammertz et al. 2010, as SVGF uses it:
// Schied et al. 2017, sec. 4.3): a 3x3 B-spline kernel whose taps lie
// denoisePass.x pixels apart, each weighted by the edge stops (rtgi_denoise.glsl)
// and by how far its luminance lies from the pixel's, against the pixel's noise (the
// square root of its variance). The variance is filtered along with the light, by the
// squared weights. The last pass (denoisePass.y = 1) multiplies the light by the base
// colour again and writes the image shown; pixels the filter keeps (alpha < 0) show
// their mean. SVGF's 5x5 kernel over 5 passes reads 125 taps a pixel, and blurs the
// variance over 3x3 on each pass: here a 3x3 kernel over 5 passes spans as far (62
// pixels) with 45 taps, and the variance is blurred once, by the first pass
// (rtgi_denoise_prepare.comp): on a software rasterizer the filter's cost is its loads.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "rtgi_common.glsl"
#include "rtgi_denoise.glsl"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;
layout(location = kDenoisePassLocation) uniform vec2 denoisePass;  // spacing, last

layout(binding = kDenoiseInImage, rgba32f) uniform readonly image2D source;
layout(binding = kDenoiseOutImage, rgba32f) uniform writeonly image2D filtered;
layout(binding = kDenoiseKeyImage, rgba32ui) uniform readonly uimage2D keys;
layout(binding = kHistoryUnit) uniform sampler2D mean;  // the accumulation target

const float kKernel[2] = float[2](1.0 / 2.0, 1.0 / 4.0);

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(rtgi.frame.zw);
  if (px.x >= size.x || px.y >= size.y) return;
  bool last = denoisePass.y > 0.5;
  vec4 c = imageLoad(source, px);
  if (c.a < 0.0) {
    imageStore(filtered, px, last ? texelFetch(mean, px, 0) : c);
    return;
  }
  DenoiseKey p = unpackDenoiseKey(imageLoad(keys, px));
  float scale = rtgi.denoise.y * length(p.position - rtgi.camera.xyz) + 1e-6;
  int step = int(denoisePass.x);
  vec4 taps[9];
  for (int k = 0; k < 9; ++k) {
    ivec2 q = px + (ivec2(k % 3, k / 3) - 1) * step;
    taps[k] = k == 4 ? c
              : any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)) ? vec4(-1.0)
                                                                              : imageLoad(source, q);
  }
  // The noise the luminance stop allows: on the first pass (taps 1 pixel apart) from
  // the variance blurred over these 3x3 pixels (SVGF eq. 5's g3x3), after it from
  // the variance as filtered so far, which is smooth already. The blur matters most
  // where a pixel's few samples all missed a rare light and measured no variance.
  float v = c.a;
  if (step == 1) {
    float sum = 0.0, weight = 0.0;
    for (int k = 0; k < 9; ++k) {
      if (taps[k].a < 0.0) continue;
      float w = kKernel[abs(k % 3 - 1)] * kKernel[abs(k / 3 - 1)];
      sum += w * taps[k].a;
      weight += w;
    }
    v = sum / weight;
  }
  if (v == 0.0) {
    // No noise: the filter would keep it as it is.
    imageStore(filtered, px, last ? vec4(c.rgb * demodulation(px), texelFetch(mean, px, 0).a) : c);
    return;
  }
  float noise = rtgi.denoise.x * sqrt(v) + 1e-6;
  float lp = luminance(c.rgb);
  // The centre's own weight: its edge stops are 1.
  float w0 = kKernel[0] * kKernel[0];
  vec3 sum = w0 * c.rgb;
  float variance = w0 * w0 * c.a, weight = w0;
  for (int k = 0; k < 9; ++k) {
    vec4 cq = taps[k];
    if (k == 4 || cq.a < 0.0) continue;
    ivec2 q = px + (ivec2(k % 3, k / 3) - 1) * step;
    float w = kKernel[abs(k % 3 - 1)] * kKernel[abs(k / 3 - 1)] *
              exp(logEdgeWeight(p, unpackDenoiseKey(imageLoad(keys, q)), scale) -
                  abs(luminance(cq.rgb) - lp) / noise);
    sum += w * cq.rgb;
    variance += w * w * cq.a;
    weight += w;
  }
  vec4 out_ = vec4(sum / weight, variance / (weight * weight));
  if (last) out_ = vec4(out_.rgb * demodulation(px), texelFetch(mean, px, 0).a);
  imageStore(filtered, px, out_);
}
