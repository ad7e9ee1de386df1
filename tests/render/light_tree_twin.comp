#version 450 core
// The GL half of the light tree twin test (light_tree_twin_gltest.cpp): one walk of
// pickLightTree per case, odd cases walking down to nodes of 8 emitters (as rtgi's
// indirect hits do) and even ones to kLightTreeLeafDraw.
#include "scene_shared.h"
#include "light_tree_shared.h"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Inputs { vec4 inputs[]; };  // p, u | n
layout(std430, binding = 1) readonly buffer Nodes { GpuLightNode nodes[]; };
layout(std430, binding = 2) writeonly buffer Outputs { vec4 outputs[]; };
layout(location = 0) uniform uint cases;

GpuLightNode lightTreeNode(int i) { return nodes[i]; }

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= cases) return;
  vec4 a = inputs[2u * i], b = inputs[2u * i + 1u];
  float pmf;
  float leafDraw = (i & 1u) != 0u ? 8.0 : kLightTreeLeafDraw;
  int pick = pickLightTree(a.w, floatBitsToUint(b.w), a.xyz, b.xyz, leafDraw, pmf);
  outputs[i] = vec4(float(pick), pmf, lightNodeImportance(nodes[0], a.xyz, b.xyz), 0.0);
}
