#version 450 core
// Appends the packed coordinates (10 bits per axis) of every occupied voxel to a
// list, for drawing voxels as cubes. Order in the list is not deterministic; what
// is drawn from it is.
#include "voxel_shared.h"

layout(local_size_x = kResolveGroupSize, local_size_y = kResolveGroupSize,
       local_size_z = kResolveGroupSize) in;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kVoxelStatsBinding) buffer Stats { VoxelStats stats; };
layout(std430, binding = kVoxelListBinding) writeonly buffer List { uint voxels[]; };
layout(binding = kAlbedoTexUnit) uniform sampler3D albedo;

void main() {
  int res = int(voxel.gridInfo.x);
  ivec3 p = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(p, ivec3(res)))) return;
  if (texelFetch(albedo, p, 0).a <= 0.0) return;
  uint slot = atomicAdd(stats.listCount, 1u);
  if (slot < uint(voxels.length())) voxels[slot] = uint(p.x) | (uint(p.y) << 10) | (uint(p.z) << 20);
}
