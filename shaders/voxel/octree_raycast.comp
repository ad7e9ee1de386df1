#version 450 core
// A batch of rays through the octree, one invocation each: the first occupied
// voxel (hit.w = 1) or a miss (hit.w = 0), and hit.xyz the voxel. For tests (the
// traversal against a dense DDA) and for measuring rays per second.
#include "octree.glsl"

layout(local_size_x = kOctreeGroupSize) in;
layout(std430, binding = kOctreeRayBinding) readonly buffer Rays { OctreeRay rays[]; };
layout(std430, binding = kOctreeRayHitBinding) writeonly buffer Hits { ivec4 hits[]; };

void main() {
  uint i = octreeInvocation();
  if (i >= octree.pass.z) return;
  OctreeRay ray = rays[i];
  MarchRay r = marchRay(ray.origin.xyz, ray.direction.xyz, ray.invDirection.xyz, ray.origin.w);
  MarchHit h = octreeTrace(r, ray.direction.w, 1 << 30);
  hits[i] = ivec4(h.voxel, h.hit ? 1 : 0);
}
