// Voxel grid layout shared by C++ and GLSL (see src/voxel/voxelize_pass.h).
#ifndef VOXGI_VOXEL_SHARED_H
#define VOXGI_VOXEL_SHARED_H

#include "gpu_types.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// Fixed-point sums: each fragment adds value x kFixedOne x weight (weight = covered
// MSAA samples, 1..4) to a uint with atomicAdd. Sums saturate at 0xFFFFFFFF (never
// wrap). A voxel takes kMaxSamplesPerVoxel = 2^32 / 2^16 = 65536 covered samples
// (16384 fully covered fragments) of the largest value before any sum could
// saturate.
VOXGI_CONST uint kFixedOne = 65535u;
VOXGI_CONST uint kSumChannels = 10u;  // albedo rgb, normal xyz, emission rgb, weight
VOXGI_CONST uint kSumAlbedo = 0u;
VOXGI_CONST uint kSumNormal = 3u;
VOXGI_CONST uint kSumEmission = 6u;
VOXGI_CONST uint kSumWeight = 9u;
VOXGI_CONST uint kSamplesPerFragment = 4u;  // 4x MSAA

// Sparse sums. A dense r32ui slot map holds, per voxel, the voxelization's epoch
// (high bits) and the voxel's slot (low kSlotBits): the first fragment of an epoch
// to reach a voxel takes the next slot. The sums live per slot, in three SSBOs of
// one uvec4 per slot, so a voxel's channels share cache lines:
//   kSlotSumsA: albedo rgb, weight   kSlotSumsN: normal xyz, 0   kSlotSumsE: emission rgb, 0
// Entries of an older epoch read as empty, so the map is never cleared per run.
VOXGI_CONST uint kSlotBits = 23u;
VOXGI_CONST uint kSlotMask = 0x7FFFFFu;    // (1 << kSlotBits) - 1
VOXGI_CONST uint kSlotFull = kSlotMask;    // claimed, but past the list's capacity
VOXGI_CONST uint kEpochCount = 512u;       // epochs 1..511, then the map is cleared
VOXGI_CONST uint kSlotHole = 0xFFFFFFFFu;  // a slot taken by a fragment that lost the race

// Image units: the slot map takes 0; the resolve pass writes the resolved grid
// through 10..12. Passes that read the resolved grid bind it as samplers on the
// texture units below.
VOXGI_CONST uint kSlotMapUnit = 0u;
VOXGI_CONST uint kResolvedUnit0 = 10u;
VOXGI_CONST uint kAlbedoTexUnit = 1u;       // rgba8: albedo rgb, opacity
VOXGI_CONST uint kNormalTexUnit = 2u;       // rgba8_snorm: unit normal (0 when ambiguous)
VOXGI_CONST uint kEmissionTexUnit = 3u;     // rgba16f: emitted radiance
VOXGI_CONST uint kVoxelParamsBinding = 1u;  // uniform block
VOXGI_CONST uint kVoxelStatsBinding = 3u;   // SSBO
VOXGI_CONST uint kVoxelListBinding = 4u;    // SSBO: packed coordinates of occupied voxels
VOXGI_CONST uint kSlotListBinding = 5u;     // SSBO: packed coordinates per slot (or a hole)
VOXGI_CONST uint kSlotSumsABinding = 6u;    // SSBO: uvec4 per slot
VOXGI_CONST uint kSlotSumsNBinding = 7u;
VOXGI_CONST uint kSlotSumsEBinding = 8u;
VOXGI_CONST uint kResolveGroupSize = 64u;  // invocations per group, one voxel each
// SSBOs are limited to 128 MiB on llvmpipe: at most 2^23 - 1 slots of 16 bytes.
VOXGI_CONST uint kMaxListEntries = 8388607u;

struct VoxelParams {
  vec4 gridOrigin;  // xyz world (scene-relative) corner, w voxel size
  vec4 gridInfo;    // x resolution, y emission fixed-point scale, z 1/scale
  uvec4 slotInfo;   // x this voxelization's epoch << kSlotBits
};

struct VoxelStats {
  uint listCount;    // slots taken (may exceed the list's capacity)
  uint checksumSum;  // order-independent hash of the resolved bytes
  uint checksumXor;
  uint capacity;  // slots (and list entries) there is room for
  uint occupied;  // voxels resolved into the list
  uint pad0, pad1, pad2;
};

#ifdef __cplusplus
static_assert(sizeof(VoxelParams) == 48);
static_assert(sizeof(VoxelStats) == 32);
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_VOXEL_SHARED_H
