// What the denoiser's stages share (rtgi_denoise_prepare.comp, rtgi_denoise.comp) and
// what accumulate needs of it for the moments (RTGI_MOMENTS). Include after
// rtgi_common.glsl.
//
// The filter follows Schied et al. 2017, "Spatiotemporal Variance-Guided Filtering"
// (SVGF), on the edge-avoiding a-trous wavelet of Dammertz et al. 2010: light is
// divided by the surface's base colour (so texture detail is not blurred, and comes
// back when the result is multiplied by it again), filtered by a 5x5 kernel whose
// taps spread 2^i pixels apart on pass i, with weights that stop at edges in depth
// and normal and where two pixels' luminances differ by more than their noise says
// they may. Unlike SVGF, the filter reads the running mean and never writes into
// it: accumulation stays as unbiased as before, and since the noise it measures is
// that of the mean, which falls as 1/n, the filter fades out as a still image
// converges.
#ifndef VOXGI_RTGI_DENOISE_GLSL
#define VOXGI_RTGI_DENOISE_GLSL

// What the light at a covered pixel is divided by: its base colour, kept away from 0
// so that black texels do not turn noise into infinities.
vec3 demodulation(ivec2 px) { return max(texelFetch(gAlbedo, px, 0).rgb, vec3(0.02)); }

// The running mean of a pixel's base colour over its samples, which accumulate keeps
// in the alpha of the direct term's mean (kDirectMeanImage, unused before) while the
// view is still: 8 bits a channel, as the G-buffer's, in an integer below 2^24 that
// a float holds exactly, plus 1 (0: none yet, after a restart, a disocclusion or a
// camera move). The denoiser divides each pixel's running mean of light by it and
// multiplies the result by it again. The G-buffer is jittered, so its base colour is
// one point of the texture each frame while the mean of light averages them all:
// divided by this frame's, the light kept the texture's detail of other frames, and
// the filter's luminance stops followed it from frame to frame (a textured wall,
// AlphaBlendModeTest at 64 frames: the denoised image changed by 1.7% RMS a frame,
// 0.18% without jitter, against 0.64% for the mean it filters).
float packAlbedoMean(vec3 albedo) {
  vec3 q = round(clamp(albedo, 0.0, 1.0) * 255.0);
  return 1.0 + q.r + 256.0 * q.g + 65536.0 * q.b;
}

vec3 unpackAlbedoMean(float code) {
  uint u = uint(max(code - 1.0, 0.0));
  return vec3(float(u & 255u), float((u >> 8u) & 255u), float(u >> 16u)) / 255.0;
}

// The normal the edge stops compare: the surface's own where a normal map tilts the
// shading normal (surfaceNormal), which the jittered G-buffer reads at another point
// of the map each frame, else the shading normal.
vec3 denoiseNormal(ivec2 px) {
  vec3 own = surfaceNormal(px);
  return own != vec3(0.0) ? own : normalize(texelFetch(gNormal, px, 0).xyz);
}

// What the denoiser divides a pixel's light by: its base colour's running mean
// (`directMeanAlpha`: the alpha of its direct term's mean), else this frame's.
vec3 denoiseAlbedo(ivec2 px, float directMeanAlpha) {
  return directMeanAlpha > 0.0 ? max(unpackAlbedoMean(directMeanAlpha), vec3(0.02))
                               : demodulation(px);
}

// Pixels the filter leaves as they are, and which lend nothing to their neighbours:
// nothing drawn, emitters (their light is exact and far brighter than what surrounds
// them) and mirrors (a reflection is an image, not noise).
bool denoiseKeeps(ivec2 px) {
  if (texelFetch(gPosition, px, 0).w < 0.5) return true;
  if (any(greaterThan(texelFetch(gEmission, px, 0).rgb, vec3(0.0)))) return true;
  float roughness = texelFetch(gNormal, px, 0).w;
  return (rtgi.flags & kRtgiHasSpecular) != 0u && roughness < kMirrorRoughness;
}

// What the edge stops compare, one rgba32ui texel per pixel (kDenoiseKeyImage),
// written by the first pass so that each tap of the others reads it in one load: the
// world position's float bits, and the normal in octahedral coordinates (11 bits
// each) with the low 10 bits of the material index.
uvec4 packDenoiseKey(vec4 position, vec3 n) {
  n /= max(abs(n.x) + abs(n.y) + abs(n.z), 1e-20);
  vec2 e = n.z >= 0.0
               ? n.xy
               : (1.0 - abs(n.yx)) * mix(vec2(-1.0), vec2(1.0), greaterThanEqual(n.xy, vec2(0.0)));
  uvec2 q = uvec2(clamp(round((e * 0.5 + 0.5) * 2047.0), 0.0, 2047.0));
  uint material = uint(position.w) & 1023u;
  return uvec4(floatBitsToUint(position.xyz), (q.x << 21u) | (q.y << 10u) | material);
}

// The two terms the a-trous passes filter (each light over base colour, rgb, and the
// variance of its luminance, or -1 where the filter keeps the pixel) in one rgba32ui
// texel of half floats, so that a tap reads both in one load (each term took an
// rgba32f image of its own before), with the square root of the variance kept
// (a variance's own range, from 1e-8 to 1e5, falls outside a half's). Light beyond
// a half's range is clamped to it.
uvec4 packDenoiseTerms(vec4 a, vec4 b) {
  const float kMax = 65504.0;
  a = vec4(min(a.rgb, vec3(kMax)), a.a < 0.0 ? -1.0 : min(sqrt(a.a), kMax));
  b = vec4(min(b.rgb, vec3(kMax)), b.a < 0.0 ? -1.0 : min(sqrt(b.a), kMax));
  return uvec4(packHalf2x16(a.rg), packHalf2x16(a.ba), packHalf2x16(b.rg), packHalf2x16(b.ba));
}

void unpackDenoiseTerms(uvec4 t, out vec4 a, out vec4 b) {
  a = vec4(unpackHalf2x16(t.x), unpackHalf2x16(t.y));
  b = vec4(unpackHalf2x16(t.z), unpackHalf2x16(t.w));
  if (a.a >= 0.0) a.a *= a.a;
  if (b.a >= 0.0) b.a *= b.a;
}

struct DenoiseKey {
  vec3 position;
  vec3 normal;
  uint material;
};

DenoiseKey unpackDenoiseKey(uvec4 k) {
  DenoiseKey d;
  d.position = uintBitsToFloat(k.xyz);
  vec2 e = vec2(float(k.w >> 21u), float((k.w >> 10u) & 2047u)) / 2047.0 * 2.0 - 1.0;
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (n.z < 0.0)
    n.xy = (1.0 - abs(n.yx)) * mix(vec2(-1.0), vec2(1.0), greaterThanEqual(n.xy, vec2(0.0)));
  d.normal = normalize(n);
  d.material = k.w & 1023u;
  return d;
}

// The log of the edge-stopping weight of pixel q for pixel p (Schied et al. 2017,
// eq. 3-4), the depth term measured as the distance of q's point from p's tangent
// plane, relative to `scale` (sigma_plane times p's distance from the camera);
// -infinity on another material.
float logEdgeWeight(DenoiseKey p, DenoiseKey q, float scale) {
  if (q.material != p.material) return -1e30;
  float c = max(dot(p.normal, q.normal), 1e-8);
  float plane = abs(dot(p.normal, q.position - p.position));
  return 128.0 * log(c) - plane / scale;
}

#endif
