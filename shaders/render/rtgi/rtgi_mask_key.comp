#version 450 core
// rtgi stage "mask", first step: what the edge detection compares, packed into one
// texel per pixel (log-luminance of the current mean, distance from the camera, 0
// where nothing is drawn, and the normal), so that it reads one texel per neighbour
// instead of three (position, normal, mean).
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;
layout(binding = kAccumImage, rgba32f) uniform readonly image2D accum;
layout(binding = kMaskKeyImage, rgba32ui) uniform writeonly uimage2D keyOut;

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (px.x >= int(rtgi.width) || px.y >= int(rtgi.height)) return;
  vec4 p = texelFetch(gPosition, px, 0);
  vec3 n = texelFetch(gNormal, px, 0).xyz;
  vec3 c = imageLoad(accum, px).rgb;
  float logLuminance = log(luminance(c) + 1e-3);
  float distance = p.w > 0.5 ? max(length(p.xyz - rtgi.camera.xyz), 1e-30) : 0.0;
  imageStore(keyOut, px,
             uvec4(floatBitsToUint(logLuminance), floatBitsToUint(distance),
                   packSnorm4x8(vec4(n, 0.0)), 0u));
}
