#version 450 core
// Runs after the raster, before the resolve: zeroes the albedo and normal of the
// voxels the previous voxelization listed that this one did not reach (their brick
// or pool entry is of an older epoch), and the emission of every voxel of the
// previous emissive list, so re-voxelizing a moving scene leaves nothing behind
// without clearing N^3. The resolve then overwrites albedo and normal of every
// voxel reached and writes emission where it is nonzero.
#include "voxel_shared.h"

layout(local_size_x = kResolveGroupSize) in;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };
layout(std430, binding = kBrickMapBinding) readonly buffer BrickMap { uint brickMap[]; };
layout(std430, binding = kBrickPoolBinding) readonly buffer BrickPool { uint pool[]; };
layout(std430, binding = kEmissiveListBinding) readonly buffer Emissive { uint emissive[]; };
layout(location = 0) uniform uint count;
layout(location = 1) uniform uint emissiveCount;

bool reached(uvec3 p) {
  uint epoch = voxel.slotInfo.x;
  uvec3 b = p / kBrickSize;
  uint brick = brickMap[b.x + voxel.slotInfo.y * (b.y + voxel.slotInfo.y * b.z)];
  // entries hold slot + 1
  if ((brick & ~kSlotMask) != epoch || (brick & kSlotMask) == kSlotFull) return false;
  uvec3 l = p % kBrickSize;
  uint entry = pool[((brick & kSlotMask) - 1u) * kBrickVoxels + (l.x | (l.y << 2) | (l.z << 4))];
  return (entry & ~kSlotMask) == epoch;
}
layout(binding = 10, rgba8) uniform writeonly image3D albedoOut;
layout(binding = 11, rgba8_snorm) uniform writeonly image3D normalOut;
layout(binding = 12, rgba16f) uniform writeonly image3D emissionOut;

void main() {
  uint i = (gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x) * kResolveGroupSize +
           gl_LocalInvocationIndex;
  if (i < emissiveCount) {
    uint code = emissive[i];
    imageStore(emissionOut, ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u),
               vec4(0.0));
  }
  if (i >= count) return;
  uint code = voxels[i];
  ivec3 p = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  if (reached(uvec3(p))) return;
  imageStore(albedoOut, p, vec4(0.0));
  imageStore(normalOut, p, vec4(0.0));
}
