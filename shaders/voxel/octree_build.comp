#version 450 core
// Octree build, one level per dispatch, one invocation per listed voxel: walk from
// the root to the voxel's node at this level; the first walker to reach a node
// without children allocates its tile of 8 (Crassin & Green, OpenGL Insights
// ch. 22: flag + allocate in one step, elected by compare-and-swap). Tiles come from
// an atomic counter; a tile past the capacity is refused and counted, and the
// C++ side re-builds into a larger buffer.
#define OCTREE_NODES_WRITABLE
#include "voxel_shared.h"
#include "octree.glsl"

layout(local_size_x = kOctreeGroupSize) in;
layout(std430, binding = kOctreeCounterBinding) coherent buffer Counters {
  OctreeCounters counters;
};
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };

const uint kPending = 0xFFFFFFFFu;

void main() {
  uint i = octreeInvocation();
  if (i >= octree.pass.z) return;
  uint code = voxels[i];
  ivec3 v = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  int depth = octreeDepth();
  int level = int(octree.pass.x);
  uint node = 0u;
  for (int l = 0; l < level; ++l) {
    uint first = octreeNodes[node];
    if (first == 0u || first == kPending) return;  // an ancestor was refused
    node = first + childIndex(v, depth, l);
  }
  if (octreeNodes[node] != 0u) return;
  if (atomicCompSwap(octreeNodes[node], 0u, kPending) != 0u) return;
  uint first = atomicAdd(counters.nodeCount, 8u);
  if (first + 8u > octree.info.w) {
    atomicAdd(counters.overflow, 1u);
    return;  // stays kPending: descendants are refused too
  }
  octreeNodes[node] = first;  // the tile is zero: the buffer is cleared before a build
}
