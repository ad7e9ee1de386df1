#version 450 core
// The GL half of the BVH twin test (bvh_twin_gltest.cpp): one traversal of
// bvh_shared.h per ray, over nodes and triangles read from SSBOs.
#include "pathtrace_shared.h"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };  // o, tMax | d, any hit
layout(std430, binding = 1) readonly buffer Nodes { GpuBvhNode nodes[]; };
layout(std430, binding = 2) readonly buffer Triangles { GpuPtTriangle triangles[]; };
layout(std430, binding = 3) writeonly buffer Outputs { vec4 outputs[]; };
layout(location = 0) uniform uint cases;

const float kInf = 1.0 / 0.0;
uint loopBudget;
GpuBvhNode loadNode(uint i) { return nodes[i]; }
GpuPtTriangle loadTriangle(uint i) { return triangles[i]; }
#include "bvh_shared.h"

void main() {
  uint c = gl_GlobalInvocationID.x;
  if (c >= cases) return;
  vec4 a = rays[2u * c], b = rays[2u * c + 1u];
  loopBudget = kPtLoopBudget;
  float t;
  uint tri;
  vec2 bc;
  bool hit = bvhTrace(a.xyz, b.xyz, 0.0, a.w, b.w > 0.5, t, tri, bc);
  outputs[c] = vec4(hit ? float(tri) : -1.0, t, bc);
}
