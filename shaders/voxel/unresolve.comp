#version 450 core
// Zeroes the resolved texels of the voxels listed by the previous voxelization,
// so re-voxelizing a moving scene leaves nothing behind (without clearing N^3).
#include "voxel_shared.h"

layout(local_size_x = kResolveGroupSize) in;

layout(std430, binding = kVoxelStatsBinding) readonly buffer Stats { VoxelStats stats; };
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };
layout(binding = 10, rgba8) uniform writeonly image3D albedoOut;
layout(binding = 11, rgba8_snorm) uniform writeonly image3D normalOut;
layout(binding = 12, rgba16f) uniform writeonly image3D emissionOut;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= min(stats.listCount, stats.capacity)) return;
  uint code = voxels[i];
  ivec3 p = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  imageStore(albedoOut, p, vec4(0.0));
  imageStore(normalOut, p, vec4(0.0));
  imageStore(emissionOut, p, vec4(0.0));
}
