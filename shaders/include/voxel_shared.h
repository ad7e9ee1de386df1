// Voxel grid layout shared by C++ and GLSL (see src/voxel/voxelize_pass.h).
#ifndef VOXGI_VOXEL_SHARED_H
#define VOXGI_VOXEL_SHARED_H

#include "gpu_types.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// Fixed-point sums: each fragment adds value x kFixedOne x weight (weight = covered
// MSAA samples, 1..4) to a r32ui image with imageAtomicAdd. Sums saturate at
// 0xFFFFFFFF (never wrap). A voxel takes kMaxSamplesPerVoxel = 2^32 / 2^16 = 65536
// covered samples (16384 fully covered fragments) of the largest value before any
// sum could saturate.
VOXGI_CONST uint kFixedOne = 65535u;
VOXGI_CONST uint kSumChannels = 10u;  // albedo rgb, normal xyz, emission rgb, weight
VOXGI_CONST uint kSumAlbedo = 0u;
VOXGI_CONST uint kSumNormal = 3u;
VOXGI_CONST uint kSumEmission = 6u;
VOXGI_CONST uint kSumWeight = 9u;
VOXGI_CONST uint kSamplesPerFragment = 4u;  // 4x MSAA

// Image units: the sums take 0..9; the resolve pass writes the resolved grid
// through 10..12. Passes that read the resolved grid bind it as samplers on the
// texture units below.
VOXGI_CONST uint kSumUnit0 = 0u;
VOXGI_CONST uint kResolvedUnit0 = 10u;
VOXGI_CONST uint kAlbedoTexUnit = 1u;       // rgba8: albedo rgb, opacity
VOXGI_CONST uint kNormalTexUnit = 2u;       // rgba8_snorm: unit normal (0 when ambiguous)
VOXGI_CONST uint kEmissionTexUnit = 3u;     // rgba16f: emitted radiance
VOXGI_CONST uint kVoxelParamsBinding = 1u;  // uniform block
VOXGI_CONST uint kVoxelStatsBinding = 3u;   // SSBO
VOXGI_CONST uint kVoxelListBinding = 4u;    // SSBO: packed coordinates of occupied voxels
VOXGI_CONST uint kResolveGroupSize = 64u;   // invocations per group, one voxel each
// SSBOs are limited to 128 MiB on llvmpipe: at most 2^25 listed voxels.
VOXGI_CONST uint kMaxListEntries = 33554432u;

struct VoxelParams {
  vec4 gridOrigin;  // xyz world (scene-relative) corner, w voxel size
  vec4 gridInfo;    // x resolution, y emission fixed-point scale, z 1/scale
};

struct VoxelStats {
  uint listCount;    // voxels touched by a fragment (may exceed the list's capacity)
  uint checksumSum;  // order-independent hash of the resolved bytes
  uint checksumXor;
  uint capacity;  // entries the list can hold
};

#ifdef __cplusplus
static_assert(sizeof(VoxelParams) == 32);
static_assert(sizeof(VoxelStats) == 16);
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_VOXEL_SHARED_H
