#version 450 core
// rtgi stage "upsample" (RenderSettings::renderScale below 1): the output's history,
// rebuilt at the output size from rtgi's frames at the internal size (temporal
// upsampling, after Karis 2014, "High quality temporal supersampling", and Yang et
// al. 2020, "A survey of temporal antialiasing techniques").
//
// Each frame rtgi's G-buffer is offset by a sub-pixel jitter, so the fresh sample of
// internal pixel q (emission plus the light its stages traced this frame) stands for
// the scene at q's jittered position. That position lies in exactly one output
// pixel, whose history adds the sample: a per-pixel sum and count, so that while
// the camera is still every output pixel converges to the mean over its own area,
// the full-resolution image. RTGI_UPSAMPLE_SCATTER runs over the internal pixels and
// adds each one's sample in place (at a scale of at most 1 no two land in one output
// pixel); the output pixels no sample reaches keep their history. What is shown
// (tonemap.frag, TONEMAP_UPSAMPLED) blends the history with rtgi's internal image.
//
// Without it, over the output pixels, on a frame after a move: the history follows
// the surface. The point output pixel p sees, on the plane of the surface its
// nearest internal sample shows, is carried back by the meshes' motion and
// projected with the previous frame's view-projection. Its count is capped
// (blend.x) and never exceeds the internal pixel's own count (rtgi's reprojection
// drops what a disocclusion made stale), and its mean is clipped, in YCoCg, to the
// internal image's 3x3 neighbourhood, widened by `blend.z` standard deviations.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#define RTGI_TRACED_IMAGE
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;

layout(std140, binding = kUpsampleParamsBinding) uniform UpsampleBlock { UpsampleParams up; };
#ifdef RTGI_UPSAMPLE_SCATTER
layout(binding = kDirectImage, rgba16f) uniform readonly image2D directIn;
layout(binding = kIndirectImage, rgba16f) uniform readonly image2D indirectIn;
layout(binding = kSpecularImage, rgba16f) uniform readonly image2D specularIn;
layout(binding = kUpsampleHistoryImage, rgba32f) uniform image2D history;
#else
layout(binding = kUpsampleHistoryImage, rgba32f) uniform writeonly image2D historyOut;
layout(binding = kUpsampleHistoryUnit) uniform sampler2D historyIn;
layout(binding = kUpsampleShownUnit) uniform sampler2D shownLow;
layout(binding = kUpsampleMeanUnit) uniform sampler2D meanLow;
layout(binding = kGMotionUnit) uniform sampler2D gMotion;
#endif

#ifdef RTGI_UPSAMPLE_SCATTER
// Internal pixel q's light of this frame, as accumulate adds it.
vec3 freshSample(ivec2 q) {
#ifdef VOXGI_NO_EMISSION
  vec3 c = vec3(0.0);
#else
  vec3 c = finiteOrZero(texelFetch(gEmission, q, 0).rgb);
#endif
  uint flags = rtgi.counts.z;
  if ((flags & kRtgiHasDirect) != 0u) c += finiteOrZero(imageLoad(directIn, q).rgb);
  if ((flags & kRtgiHasIndirect) != 0u) c += finiteOrZero(imageLoad(indirectIn, q).rgb);
  if ((flags & kRtgiHasSpecular) != 0u) c += finiteOrZero(imageLoad(specularIn, q).rgb);
  return c;
}

#else
vec3 toYCoCg(vec3 c) {
  return vec3(0.25 * c.r + 0.5 * c.g + 0.25 * c.b, 0.5 * c.r - 0.5 * c.b,
              -0.25 * c.r + 0.5 * c.g - 0.25 * c.b);
}

vec3 fromYCoCg(vec3 c) { return vec3(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z); }

// The history's mean clipped towards the centre of the box mean +- width x sigma of
// the internal image around q (variance clipping, Salvi 2016), in YCoCg.
vec3 clipToNeighbourhood(vec3 history, ivec2 q, ivec2 lowSize) {
  vec3 m1 = vec3(0.0), m2 = vec3(0.0);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      vec3 c =
          toYCoCg(texelFetch(shownLow, clamp(q + ivec2(dx, dy), ivec2(0), lowSize - 1), 0).rgb);
      m1 += c;
      m2 += c * c;
    }
  m1 /= 9.0;
  vec3 sigma = sqrt(max(m2 / 9.0 - m1 * m1, vec3(0.0)));
  vec3 extent = up.blend.z * sigma + 1e-6;
  vec3 h = toYCoCg(history);
  vec3 offset = h - m1;
  vec3 units = abs(offset / extent);
  float beyond = max(units.x, max(units.y, units.z));
  return beyond > 1.0 ? fromYCoCg(m1 + offset / beyond) : history;
}

// The output's history at the point p shows, from where that point was last frame:
// (sum, count), or 0 where it was off screen or nothing is drawn.
vec4 reprojectedHistory(ivec2 p, ivec2 q, ivec2 outSize) {
  vec4 g = texelFetch(gPosition, q, 0);
  if (g.w < 0.5) return vec4(0.0);
  vec3 n = normalize(texelFetch(gNormal, q, 0).xyz);
  mat4 inverseViewProj = mat4(up.inverseViewProj[0], up.inverseViewProj[1], up.inverseViewProj[2],
                              up.inverseViewProj[3]);
  vec2 ndc = (vec2(p) + 0.5) / vec2(outSize) * 2.0 - 1.0;
  vec4 far = inverseViewProj * vec4(ndc, 0.5, 1.0);
  vec3 d = normalize(far.xyz / far.w - up.camera.xyz);
  // Where p's ray meets the plane of the surface q shows; q's own point where the
  // ray grazes it.
  vec3 x = g.xyz;
  float dn = dot(d, n);
  if (abs(dn) > 1e-3) {
    float t = dot(g.xyz - up.camera.xyz, n) / dn;
    if (t > 0.0) x = up.camera.xyz + t * d;
  }
  vec3 was = x + texelFetch(gMotion, q, 0).xyz;
  mat4 previous = mat4(up.previousViewProj[0], up.previousViewProj[1], up.previousViewProj[2],
                       up.previousViewProj[3]);
  vec4 clip = previous * vec4(was, 1.0);
  if (!(clip.w > 0.0)) return vec4(0.0);
  vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return vec4(0.0);
  return textureLod(historyIn, uv, 0.0);
}

#endif

#ifdef RTGI_UPSAMPLE_SCATTER
void main() {
  ivec2 q = ivec2(gl_GlobalInvocationID.xy);
  ivec2 lowSize = ivec2(rtgi.frame.zw);
  if (q.x >= lowSize.x || q.y >= lowSize.y || outside(q)) return;
  ivec2 outSize = ivec2(up.size.xy);
  // q's sample lies at q + 0.5 - jitter, in internal pixels.
  vec2 ratio = vec2(lowSize) / vec2(outSize);
  ivec2 p = ivec2(floor((vec2(q) + 0.5 - up.jitter.xy) / ratio));
  if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, outSize))) return;
  imageStore(history, p, imageLoad(history, p) + vec4(freshSample(q), 1.0));
}
#else
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 outSize = ivec2(up.size.xy);
  if (p.x >= outSize.x || p.y >= outSize.y) return;
  ivec2 lowSize = ivec2(rtgi.frame.zw);
  // The internal pixel whose jittered sample is nearest to p's centre.
  vec2 ratio = vec2(lowSize) / vec2(outSize);
  ivec2 q = clamp(ivec2(floor((vec2(p) + 0.5) * ratio + up.jitter.xy)), ivec2(0), lowSize - 1);
  vec4 h = reprojectedHistory(p, q, outSize);
  float count = min(h.a, min(up.blend.x, texelFetch(meanLow, q, 0).a));
  if (h.a > 1e-3 && count > 0.0)
    h = vec4(clipToNeighbourhood(h.rgb / h.a, q, lowSize) * count, count);
  else
    h = vec4(0.0);
  imageStore(historyOut, p, h);
}
#endif
