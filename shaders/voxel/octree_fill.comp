#version 450 core
// Octree leaves, one invocation per listed voxel: mark the leaf occupied and copy
// the resolved voxel into it. A two-sided leaf (octree.glsl, leafAxis) takes the
// index of its second light slot, in its normal word.
#define OCTREE_NODES_WRITABLE
#include "voxel_shared.h"
#include "octree.glsl"

layout(local_size_x = kOctreeGroupSize) in;
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };
layout(std430, binding = kOctreeCounterBinding) coherent buffer Counters {
  OctreeCounters counters;
};
layout(std430, binding = kOctreeMaterialBinding) writeonly buffer Material { uvec2 material[]; };
layout(std430, binding = kOctreeEmissionBinding) writeonly buffer Emission { uint emission[]; };
layout(std430, binding = kVoxelAttribBinding) readonly buffer Attributes { uvec4 attributes[]; };

void main() {
  uint i = octreeInvocation();
  if (i >= octree.pass.z) return;
  uint code = voxels[i];
  ivec3 v = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  int depth = octreeDepth();
  uint node = 0u;
  for (int l = 0; l < depth; ++l) node = octreeNodes[node] + childIndex(v, depth, l);
  octreeNodes[node] = kOctreeLeafOccupied;
  uvec4 a = attributes[i];  // albedo + opacity, normal: the formats the nodes keep
  uvec2 m = a.xy;
  if (leafAxis(m.y) >= 0) {
    // Past 2^24 - 1 two-sided leaves, the rest keep one light for both sides.
    uint index = atomicAdd(counters.twoSided, 1u);
    m.y = index < 0xFFFFFFu ? (m.y & 0xFF000000u) | index : 0u;
  }
  material[node] = m;
  emission[node] = packRgb9e5(vec3(unpackHalf2x16(a.z), unpackHalf2x16(a.w).x));
}
