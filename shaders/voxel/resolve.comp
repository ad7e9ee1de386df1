#version 450 core
// Voxel resolve, one group per pool brick and one invocation per voxel of it:
// fixed-point sums -> averaged attributes in the formats the later stages read,
// and the voxel appended to the list of occupied voxels. The sums are zeroed as
// they are read, so the next voxelization starts clean. A group's writes stay
// within one brick of the grid.
// Also an order-independent checksum of the resolved values (a sum and an xor of
// per-voxel hashes of index and values as quantised to the stored formats).
#include "voxel_shared.h"

layout(local_size_x = kResolveGroupSize) in;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kVoxelStatsBinding) buffer Stats { VoxelStats stats; };
layout(std430, binding = kVoxelListBinding) writeonly buffer List { uint voxels[]; };
layout(std430, binding = kEmissiveListBinding) writeonly buffer Emissive { uint emissive[]; };
layout(std430, binding = kBrickPoolBinding) readonly buffer BrickPool { uint pool[]; };
layout(std430, binding = kBrickListBinding) readonly buffer BrickList { uint brickVoxels[]; };
layout(std430, binding = kSlotSumsABinding) buffer SumsA { uvec4 sumsA[]; };
layout(std430, binding = kSlotSumsNBinding) buffer SumsN { uvec4 sumsN[]; };
layout(std430, binding = kSlotSumsEBinding) buffer SumsE { uvec4 sumsE[]; };

layout(binding = 10, rgba8) uniform writeonly image3D albedoOut;
layout(binding = 11, rgba8_snorm) uniform writeonly image3D normalOut;
layout(binding = 12, rgba16f) uniform writeonly image3D emissionOut;

uint hash(uint x) {  // a 32-bit integer mix (lowbias32)
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

void main() {
  uint brick = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  if (brick >= min(stats.brickCount, stats.brickCapacity)) return;
  uint l = gl_LocalInvocationIndex;
  uint entry = pool[brick * kBrickVoxels + l];
  if ((entry & ~kSlotMask) != voxel.slotInfo.x) return;  // not reached in this epoch
  uint i = (entry & kSlotMask) - 1u;  // entries hold slot + 1
  uint b = brickVoxels[brick];
  uvec3 pu = uvec3(b & 1023u, (b >> 10) & 1023u, (b >> 20) & 1023u) * kBrickSize +
             uvec3(l & 3u, (l >> 2) & 3u, l >> 4);
  ivec3 p = ivec3(pu);
  uint code = pu.x | (pu.y << 10) | (pu.z << 20);
  int res = int(voxel.gridInfo.x);

  uvec4 sa = sumsA[i];
  uvec4 sn = sumsN[i];
  uvec4 se = sumsE[i];
#ifndef VOXGI_KEEP_SUMS  // tests inspect the sums after the resolve
  sumsA[i] = uvec4(0u);
  sumsN[i] = uvec4(0u);
  if (se != uvec4(0u)) sumsE[i] = uvec4(0u);
#endif
  uint w = sa.w;
  float inv = 1.0 / (float(w) * float(kFixedOne));
  vec3 albedo = vec3(sa.xyz) * inv;
  vec3 normal = vec3(sn.xyz) * inv * 2.0 - 1.0;
  vec3 emission = vec3(se.xyz) * inv * voxel.gridInfo.z;
  // Opposite normals cancel (a voxel holding both sides of a thin wall): no normal.
  float len = length(normal);
  normal = len > 0.1 ? normal / len : vec3(0.0);
  // Coverage: one fully covered fragment makes a voxel opaque.
  float opacity = min(1.0, float(w) / float(kSamplesPerFragment));
  vec4 a = vec4(albedo, opacity);
  vec4 n = vec4(normal, 0.0);
  vec4 e = vec4(emission, 0.0);
  imageStore(albedoOut, p, a);
  imageStore(normalOut, p, n);
  // The emission texture is zero except at the voxels of the emissive list, which
  // the next voxelization zeroes first: most voxels need no emission store.
  if (se != uvec4(0u)) {
    imageStore(emissionOut, p, e);
    emissive[atomicAdd(stats.emissive, 1u)] = code;
  }
  voxels[atomicAdd(stats.occupied, 1u)] = code;

  uint index = uint(p.x + res * (p.y + res * p.z));
  uint h = hash(index ^ 0x9e3779b9u);
  h = hash(h ^ packUnorm4x8(a));
  h = hash(h ^ packSnorm4x8(n));
  h = hash(h ^ packHalf2x16(e.rg));
  h = hash(h ^ packHalf2x16(e.ba));
  atomicAdd(stats.checksumSum, h);
  atomicXor(stats.checksumXor, hash(h + 0x632be5abu));
}
