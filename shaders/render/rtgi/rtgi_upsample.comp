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
// the full-resolution image. One invocation per internal pixel adds its sample in
// place (at a scale of at most 1 no two land in one output pixel); the output
// pixels no sample reaches keep their history. What is shown (tonemap.frag,
// TONEMAP_UPSAMPLED) blends the history with rtgi's internal image, which carries
// the image across camera moves: a move restarts the output's history
// (RtgiPass::upsample).
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#define RTGI_TRACED_IMAGE
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;

layout(std140, binding = kUpsampleParamsBinding) uniform UpsampleBlock { UpsampleParams up; };
layout(binding = kDirectImage, rgba16f) uniform readonly image2D directIn;
layout(binding = kIndirectImage, rgba16f) uniform readonly image2D indirectIn;
layout(binding = kSpecularImage, rgba16f) uniform readonly image2D specularIn;
layout(binding = kUpsampleHistoryImage, rgba32f) uniform image2D history;

// Internal pixel q's light of this frame, as accumulate adds it.
vec3 freshSample(ivec2 q) {
#ifdef VOXGI_NO_EMISSION
  vec3 c = vec3(0.0);
#else
  vec3 c = finiteOrZero(texelFetch(gEmission, q, 0).rgb);
#endif
  uint flags = rtgi.flags;
  if ((flags & kRtgiHasDirect) != 0u) c += finiteOrZero(imageLoad(directIn, q).rgb);
  if ((flags & kRtgiHasIndirect) != 0u) c += finiteOrZero(imageLoad(indirectIn, q).rgb);
  if ((flags & kRtgiHasSpecular) != 0u) c += finiteOrZero(imageLoad(specularIn, q).rgb);
  return c;
}

void main() {
  ivec2 q = ivec2(gl_GlobalInvocationID.xy);
  ivec2 lowSize = ivec2(rtgi.width, rtgi.height);
  if (q.x >= lowSize.x || q.y >= lowSize.y || outside(q)) return;
  ivec2 outSize = ivec2(up.size.xy);
  // q's sample lies at q + 0.5 - jitter, in internal pixels.
  vec2 ratio = vec2(lowSize) / vec2(outSize);
  ivec2 p = ivec2(floor((vec2(q) + 0.5 - up.jitter.xy) / ratio));
  if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, outSize))) return;
  imageStore(history, p, imageLoad(history, p) + vec4(freshSample(q), 1.0));
}
