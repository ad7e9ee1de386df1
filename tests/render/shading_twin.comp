#version 450 core
// The GL half of the shading twin test (see shading_twin.h).
#include "scene_shared.h"
#include "pathtrace_shared.h"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Inputs { vec4 inputs[]; };
layout(std430, binding = 1) readonly buffer Emissive { GpuPtEmissive emissive[]; };
layout(std430, binding = 2) readonly buffer Texels { uint texels[]; };
layout(std430, binding = 3) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = 4) writeonly buffer Outputs { vec4 outputs[]; };
layout(location = 0) uniform uvec4 counts;   // x cases, y emitters, z lights
layout(location = 1) uniform uvec4 texture;  // the texture's table entry

#define VOXGI_TABLES_PARAM
#define VOXGI_TABLES_ARG
#define VOXGI_EMISSIVE(i) emissive[i]
#define VOXGI_TEXEL(i) texels[i]
#include "shading_twin.h"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= counts.x) return;
  uint a = i * kTwinInputs;
  uint o = i * kTwinOutputs;
  vec4 r[11];
  twinCase(inputs[a], inputs[a + 1u], inputs[a + 2u], inputs[a + 3u], inputs[a + 4u], counts.y,
           lights[i % counts.z], texture, r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8],
           r[9], r[10]);
  for (uint k = 0u; k < kTwinOutputs; ++k) outputs[o + k] = r[k];
}
