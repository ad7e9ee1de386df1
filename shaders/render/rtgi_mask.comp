#version 450 core
// rtgi stage "mask", first half: where the accumulated image is still noisy. Edge
// detection on the log-luminance of the current mean: the absolute Laplacian over
// the 3x3 neighbourhood, taking only neighbours on the same surface (similar normal
// and depth), so silhouettes and creases, which stay, do not read as noise while
// speckle, which accumulation removes, does.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;
layout(binding = kAccumImage, rgba32f) uniform readonly image2D accum;
layout(binding = kEdgeImage, r16f) uniform writeonly image2D edgeOut;

float logLuminance(ivec2 px) {
  vec3 c = imageLoad(accum, px).rgb;
  return log(dot(c, vec3(0.2126, 0.7152, 0.0722)) + 1e-3);
}

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(rtgi.frame.zw);
  if (px.x >= size.x || px.y >= size.y) return;
  vec4 p0 = texelFetch(gPosition, px, 0);
  vec3 n0 = texelFetch(gNormal, px, 0).xyz;
  float d0 = length(p0.xyz - rtgi.camera.xyz);
  float centre = logLuminance(px);
  float sum = 0.0, weight = 0.0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = clamp(px + ivec2(dx, dy), ivec2(0), size - 1);
      if (q == px) continue;
      vec4 p1 = texelFetch(gPosition, q, 0);
      vec3 n1 = texelFetch(gNormal, q, 0).xyz;
      float d1 = length(p1.xyz - rtgi.camera.xyz);
      bool same = p0.w == p1.w && dot(n0, n1) > 0.9 && abs(d1 - d0) < 0.05 * d0;
      if (!same) continue;
      sum += logLuminance(q);
      weight += 1.0;
    }
  }
  float edge = weight > 0.0 ? abs(centre - sum / weight) : 0.0;
  imageStore(edgeOut, px, vec4(p0.w > 0.5 ? edge : 0.0));
}
