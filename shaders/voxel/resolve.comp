#version 450 core
// Voxel resolve, one invocation per voxel slot taken by the raster: fixed-point sums
// -> averaged attributes, written at the slot's index of the list of occupied
// voxels (the raster wrote the coordinates there when it took the slot; see
// voxel_shared.h). The sums are zeroed as they are read, so the next voxelization
// starts clean. Also an order-independent checksum of the resolved values (a sum
// and an xor of per-voxel hashes of index and values as quantised to the stored
// formats), unless VOXGI_NO_CHECKSUM.
#include "voxel_shared.h"

layout(local_size_x = kResolveGroupSize) in;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kVoxelStatsBinding) buffer Stats { VoxelStats stats; };
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };
layout(std430, binding = kVoxelAttribBinding) writeonly buffer Attributes { uvec4 attributes[]; };
layout(std430, binding = kSlotSumsABinding) buffer SumsA { uvec4 sumsA[]; };
layout(std430, binding = kSlotSumsNBinding) buffer SumsN { uvec4 sumsN[]; };
layout(std430, binding = kSlotSumsEBinding) buffer SumsE { uvec4 sumsE[]; };

uint hash(uint x) {  // a 32-bit integer mix (lowbias32)
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

void main() {
  uint i = (gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x) * kResolveGroupSize +
           gl_LocalInvocationIndex;
  if (i >= voxel.limits.z) return;
  uint code = voxels[i];
  uvec3 p = uvec3(code & 1023u, (code >> 10) & 1023u, code >> 20);

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
  // Opposite normals cancel (a voxel holding both sides of a thin wall): no normal,
  // and the axis they lie along (the largest second moment) coded in w, so the
  // octree keeps the light of the two sides apart (octree.glsl, leafAxis).
  float len = length(normal);
  vec2 mxy = vec2(sn.w, se.w) / (float(w) * float(kMomentOne));
  vec3 moments = vec3(mxy, 1.0 - mxy.x - mxy.y);
  int axis =
      moments.x >= moments.y ? (moments.x >= moments.z ? 0 : 2) : (moments.y >= moments.z ? 1 : 2);
  float sided = len > 0.1 ? 0.0 : float(axis + 1) * 0.25;
  normal = len > 0.1 ? normal / len : vec3(0.0);
  // Coverage: one fully covered fragment makes a voxel opaque.
  float opacity = min(1.0, float(w) / float(kSamplesPerFragment));
  uvec4 a = uvec4(packUnorm4x8(vec4(albedo, opacity)), packSnorm4x8(vec4(normal, sided)),
                  packHalf2x16(emission.rg), packHalf2x16(vec2(emission.b, 0.0)));
  attributes[i] = a;

#ifndef VOXGI_NO_CHECKSUM
  uint res = uint(voxel.gridInfo.x);
  uint h = hash((p.x + res * (p.y + res * p.z)) ^ 0x9e3779b9u);
  h = hash(h ^ a.x);
  h = hash(h ^ a.y);
  h = hash(h ^ a.z);
  h = hash(h ^ a.w);
  atomicAdd(stats.checksumSum, h);
  atomicXor(stats.checksumXor, hash(h + 0x632be5abu));
#endif
}
