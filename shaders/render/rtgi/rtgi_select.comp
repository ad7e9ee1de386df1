#version 450 core
// rtgi stage "select": which pixels trace this frame under a frame budget. Every
// pixel keeps its turn in the interleave pattern (so every pixel converges); on top,
// the pixels whose work mask exceeds the threshold the budget chose (kSelectMask),
// or a random fraction of the others (kSelectUniform: the same cost spread
// uniformly, for comparison). They are appended to the pixel list the tracing
// stages run over, and marked for accumulate.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;
layout(binding = kMaskImage, r16f) uniform readonly image2D maskIn;
layout(binding = kTracedImage, r8ui) uniform writeonly uimage2D tracedOut;
layout(std430, binding = kPixelListBinding) buffer PixelList {
  PixelListHeader header;
  uint pixels[];
};

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (px.x >= int(rtgi.width) || px.y >= int(rtgi.height)) return;
  float level = uintBitsToFloat(rtgi.selectLevel);
  bool trace = tracesThisFrame(px);
  if (!trace && rtgi.selectKind == kSelectMask) trace = imageLoad(maskIn, px).x > level;
  if (!trace && rtgi.selectKind == kSelectUniform) {
    uint h = pcgHash(pcgHash(uint(px.y) * rtgi.width + uint(px.x)) ^ pcgHash(rtgi.frameIndex));
    trace = float(h >> 8u) * (1.0 / 16777216.0) < level;
  }
  imageStore(tracedOut, px, uvec4(trace ? 1u : 0u));
  if (!trace) return;
  uint slot = atomicAdd(header.count.x, 1u);
  pixels[slot] = uint(px.x) | (uint(px.y) << 16u);
  atomicMax(header.groups.x, slot / kRtgiTraceGroup + 1u);
}
