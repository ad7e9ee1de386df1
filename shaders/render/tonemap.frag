#version 450 core
// Linear HDR radiance -> display: exposure, an operator, then the sRGB transfer
// function (written by hand, so the 8-bit output is exactly what gets saved).
#include "scene_shared.h"

layout(binding = kHdrInputUnit) uniform sampler2D hdr;
layout(location = kExposureLocation) uniform float exposure;
layout(location = kTonemapLocation) uniform int op;
layout(location = kTonemapInputScaleLocation) uniform vec2 inputScale;  // the mask view's

layout(location = 0) out vec4 outColor;

#ifdef TONEMAP_UPSAMPLED
// rtgi at a render scale below 1 (rtgi_upsample.comp): the radiance shown is the
// output pixel's own samples (their sum and count) with rtgi's internal image, read
// with a bilinear filter, which weighs as `internalWeight` samples: it fills in
// where the pixel has few of its own and fades as they come. It is written beside
// the display image, as the HDR image the renderer reads back.
layout(binding = kUpsampleHistoryUnit) uniform sampler2D history;
layout(binding = kUpsampleShownUnit) uniform sampler2D shownLow;
layout(location = kUpsampleWeightLocation) uniform float internalWeight;
layout(location = 1) out vec4 outHdr;

vec3 radiance() {
  vec4 h = texelFetch(history, ivec2(gl_FragCoord.xy), 0);
  vec3 low = textureLod(shownLow, gl_FragCoord.xy / vec2(textureSize(history, 0)), 0.0).rgb;
  vec3 c = (h.rgb + internalWeight * low) / (h.a + internalWeight);
  outHdr = vec4(c, h.a);
  return c;
}
#else
vec3 radiance() { return texelFetch(hdr, ivec2(gl_FragCoord.xy), 0).rgb; }
#endif

vec3 acesFitted(vec3 x) {  // Narkowicz 2015, ACES filmic curve fit
  return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 srgbEncode(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

void main() {
  if (op == kTonemapMask) {
    outColor =
        vec4(srgbEncode(vec3(texelFetch(hdr, ivec2(gl_FragCoord.xy * inputScale), 0).r)), 1.0);
    return;
  }
  vec3 c = radiance() * exposure;
  if (any(isnan(c)) || any(isinf(c))) c = vec3(1.0, 0.0, 1.0);  // make bad pixels loud
  if (op == kTonemapAces) c = acesFitted(c);
  outColor = vec4(srgbEncode(c), 1.0);
}
