#version 450 core
// rtgi stage "mask", edges: where the accumulated image is still noisy. Edge
// detection on the log-luminance of the current mean: the absolute Laplacian over
// the 3x3 neighbourhood, taking only neighbours on the same surface (similar normal
// and depth), so silhouettes and creases, which stay, do not read as noise while
// speckle, which accumulation removes, does. Reads the keys rtgi_mask_key.comp
// packed: one texel per neighbour.
#include "rtgi_shared.h"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;
layout(std140, binding = kRtgiParamsBinding) uniform RtgiBlock { RtgiParams rtgi; };
layout(binding = kMaskKeyImage, rgba32ui) uniform readonly uimage2D keys;
layout(binding = kEdgeImage, r16f) uniform writeonly image2D edgeOut;

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(rtgi.width, rtgi.height);
  if (px.x >= size.x || px.y >= size.y) return;
  uvec4 k0 = imageLoad(keys, px);
  float centre = uintBitsToFloat(k0.x);
  float d0 = uintBitsToFloat(k0.y);  // 0: nothing drawn
  vec3 n0 = unpackSnorm4x8(k0.z).xyz;
  float sum = 0.0, weight = 0.0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = clamp(px + ivec2(dx, dy), ivec2(0), size - 1);
      if (q == px) continue;
      uvec4 k1 = imageLoad(keys, q);
      float d1 = uintBitsToFloat(k1.y);
      vec3 n1 = unpackSnorm4x8(k1.z).xyz;
      if (!sameSurface(d0 > 0.0, n0, d0, d1 > 0.0, n1, d1)) continue;
      sum += uintBitsToFloat(k1.x);
      weight += 1.0;
    }
  }
  float edge = weight > 0.0 ? abs(centre - sum / weight) : 0.0;
  imageStore(edgeOut, px, vec4(d0 > 0.0 ? edge : 0.0));
}
