#version 450 core
// Voxel resolve: fixed-point sums -> averaged attributes in the formats the later
// stages read, plus the occupied count and an order-independent checksum of the
// resolved bytes (a sum and an xor of per-voxel hashes of index and bytes).
#include "voxel_shared.h"

layout(local_size_x = kResolveGroupSize, local_size_y = kResolveGroupSize,
       local_size_z = kResolveGroupSize) in;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kVoxelStatsBinding) buffer Stats { VoxelStats stats; };

layout(binding = 0, r32ui) uniform readonly uimage3D sums[kSumChannels];
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
  int res = int(voxel.gridInfo.x);
  ivec3 p = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(p, ivec3(res)))) return;
  uint w = imageLoad(sums[kSumWeight], p).x;
  if (w == 0u) {
    imageStore(albedoOut, p, vec4(0.0));
    imageStore(normalOut, p, vec4(0.0));
    imageStore(emissionOut, p, vec4(0.0));
    return;
  }
  float inv = 1.0 / (float(w) * float(kFixedOne));
  vec3 albedo, normal, emission;
  for (int c = 0; c < 3; ++c) {
    albedo[c] = float(imageLoad(sums[int(kSumAlbedo) + c], p).x) * inv;
    normal[c] = float(imageLoad(sums[int(kSumNormal) + c], p).x) * inv * 2.0 - 1.0;
    emission[c] = float(imageLoad(sums[int(kSumEmission) + c], p).x) * inv;
  }
  emission *= voxel.gridInfo.z;
  // Opposite normals cancel (a voxel holding both sides of a thin wall): no normal.
  float len = length(normal);
  normal = len > 0.1 ? normal / len : vec3(0.0);
  // Coverage: one fully covered fragment per voxel is opaque.
  float opacity = min(1.0, float(w) / float(kSamplesPerFragment));
  vec4 a = vec4(albedo, opacity);
  vec4 n = vec4(normal, 0.0);
  vec4 e = vec4(emission, 0.0);
  imageStore(albedoOut, p, a);
  imageStore(normalOut, p, n);
  imageStore(emissionOut, p, e);

  // Checksum over the bytes as stored (quantised like the formats above).
  uint index = uint(p.x + res * (p.y + res * p.z));
  uint h = hash(index ^ 0x9e3779b9u);
  h = hash(h ^ packUnorm4x8(a));
  h = hash(h ^ packSnorm4x8(n));
  h = hash(h ^ packHalf2x16(e.rg));
  h = hash(h ^ packHalf2x16(e.ba));
  atomicAdd(stats.occupied, 1u);
  atomicAdd(stats.checksumSum, h);
  atomicXor(stats.checksumXor, hash(h + 0x632be5abu));
}
