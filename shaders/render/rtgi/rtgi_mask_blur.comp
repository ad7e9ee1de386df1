#version 450 core
// rtgi stage "mask", second half: a 5x5 box blur fills the noisy areas the edges
// found into the work mask, mapped to [0, 1) (m / (1 + m)), and counted into a
// histogram the frame budget reads to place its threshold.
#include "rtgi_shared.h"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;
layout(std140, binding = kRtgiParamsBinding) uniform RtgiBlock { RtgiParams rtgi; };
layout(binding = kEdgeImage, r16f) uniform readonly image2D edgeIn;
layout(binding = kMaskImage, r16f) uniform writeonly image2D maskOut;
layout(std430, binding = kMaskHistogramBinding) buffer Histogram { uint histogram[]; };

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(rtgi.width, rtgi.height);
  if (px.x >= size.x || px.y >= size.y) return;
  float sum = 0.0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx)
      sum += imageLoad(edgeIn, clamp(px + ivec2(dx, dy), ivec2(0), size - 1)).x;
  float m = sum / 25.0;
  m = m / (1.0 + m);
  imageStore(maskOut, px, vec4(m));
  atomicAdd(histogram[min(uint(m * float(kMaskBins)), kMaskBins - 1u)], 1u);
}
