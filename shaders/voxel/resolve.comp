#version 450 core
// Voxel resolve, one invocation per listed voxel: fixed-point sums -> averaged
// attributes in the formats the later stages read. The sums are zeroed as they
// are read, so the next voxelization starts clean without clearing N^3 texels.
// Also an order-independent checksum of the resolved values (a sum and an xor of
// per-voxel hashes of index and values as quantised to the stored formats).
#include "voxel_shared.h"

layout(local_size_x = kResolveGroupSize) in;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kVoxelStatsBinding) buffer Stats { VoxelStats stats; };
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };

layout(binding = 0, r32ui) uniform uimage3D sums[kSumChannels];
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

uint take(int channel, ivec3 p) {
  uint v = imageLoad(sums[channel], p).x;
#ifndef VOXGI_KEEP_SUMS  // tests inspect the sums after the resolve
  imageStore(sums[channel], p, uvec4(0u));
#endif
  return v;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= min(stats.listCount, stats.capacity)) return;
  uint code = voxels[i];
  ivec3 p = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  int res = int(voxel.gridInfo.x);

  uint w = take(9, p);
  float inv = 1.0 / (float(w) * float(kFixedOne));
  vec3 albedo = vec3(take(0, p), take(1, p), take(2, p)) * inv;
  vec3 normal = vec3(take(3, p), take(4, p), take(5, p)) * inv * 2.0 - 1.0;
  vec3 emission = vec3(take(6, p), take(7, p), take(8, p)) * inv * voxel.gridInfo.z;
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
  imageStore(emissionOut, p, e);

  uint index = uint(p.x + res * (p.y + res * p.z));
  uint h = hash(index ^ 0x9e3779b9u);
  h = hash(h ^ packUnorm4x8(a));
  h = hash(h ^ packSnorm4x8(n));
  h = hash(h ^ packHalf2x16(e.rg));
  h = hash(h ^ packHalf2x16(e.ba));
  atomicAdd(stats.checksumSum, h);
  atomicXor(stats.checksumXor, hash(h + 0x632be5abu));
}
