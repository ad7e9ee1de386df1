#version 450 core
// The GL half of the interleave twin test (interleave_twin_gltest.cpp): each
// function of interleave_shared.h on one case.
#include "interleave_shared.h"

layout(local_size_x = 64) in;

// Per case: x invocation, y width, z height, w interleave | frame << 8 | sparse << 31.
layout(std430, binding = 0) readonly buffer Inputs { uvec4 inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { uvec4 outputs[]; };
layout(location = 0) uniform uint cases;

void main() {
  uint c = gl_GlobalInvocationID.x;
  if (c >= cases) return;
  uvec4 a = inputs[c];
  uint n = a.w & 255u;
  uint frame = (a.w >> 8u) & 0xffffu;
  bool every = interleaveEveryPixel(n, frame, (a.w >> 31u) != 0u);
  ivec2 px = ivec2(-1);
  bool ok = interleavePixel(a.x, a.y, a.z, n, frame, every, px);
  ivec2 q = ivec2(int(a.x % 61u), int(a.x / 61u));
  outputs[c] =
      uvec4((ok ? 1u : 0u) | (every ? 2u : 0u) | (interleaveTraces(q, n, frame) ? 4u : 0u) |
                (interleaveTurn(n, frame) << 3u) | (interleaveRank(q) << 8u) |
                (interleaveCell(a.x & 15u) << 12u),
            uint(px.x), uint(px.y), interleaveTraceCount(a.y, a.z, n, every));
}
