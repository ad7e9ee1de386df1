#version 450 core
// Runs after the raster, before the resolve: zeroes the resolved texels of the
// voxels the previous voxelization listed that this one did not reach (their slot
// map entry is of an older epoch), so re-voxelizing a moving scene leaves nothing
// behind without clearing N^3. Voxels reached again are overwritten by the resolve.
#include "voxel_shared.h"

layout(local_size_x = kResolveGroupSize) in;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };
layout(location = 0) uniform uint count;
layout(binding = kSlotMapUnit, r32ui) uniform readonly uimage3D slotMap;
layout(binding = 10, rgba8) uniform writeonly image3D albedoOut;
layout(binding = 11, rgba8_snorm) uniform writeonly image3D normalOut;
layout(binding = 12, rgba16f) uniform writeonly image3D emissionOut;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  uint code = voxels[i];
  ivec3 p = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  if ((imageLoad(slotMap, p).x & ~kSlotMask) == voxel.slotInfo.x) return;
  imageStore(albedoOut, p, vec4(0.0));
  imageStore(normalOut, p, vec4(0.0));
  imageStore(emissionOut, p, vec4(0.0));
}
