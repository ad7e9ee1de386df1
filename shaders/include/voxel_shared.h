// Voxel grid layout shared by C++ and GLSL (see src/voxel/voxelize_pass.h).
#ifndef VOXGI_VOXEL_SHARED_H
#define VOXGI_VOXEL_SHARED_H

#include "bindings_shared.h"
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
VOXGI_CONST uint kMomentOne = 255u;   // a normal's squared component of 1 (voxelMoments)
VOXGI_CONST uint kSumChannels = 10u;  // albedo rgb, normal xyz, emission rgb, weight
VOXGI_CONST uint kSumAlbedo = 0u;
VOXGI_CONST uint kSumNormal = 3u;
VOXGI_CONST uint kSumEmission = 6u;
VOXGI_CONST uint kSumWeight = 9u;
VOXGI_CONST uint kSamplesPerFragment = 4u;  // 4x MSAA

// Sparse sums, two levels. A brick map holds, per brick of 4^3 voxels, the
// voxelization's epoch (high bits) and the brick's slot in a pool (low kSlotBits);
// each pool brick holds, per voxel, the epoch and the voxel's slot. The first
// fragment of an epoch to reach a brick or a voxel takes the next slot. Entries of
// an older epoch read as empty, so neither level is cleared per run, and the small
// map and the compact pool keep the lookups local. The sums live per voxel slot,
// in three SSBOs of one uvec4 per slot, so a voxel's channels share cache lines:
//   kSlotSumsA: albedo rgb, weight   kSlotSumsN: normal xyz, 0   kSlotSumsE: emission rgb, 0
// (the bindings are in bindings_shared.h).
VOXGI_CONST uint kSlotBits = 23u;
VOXGI_CONST uint kSlotMask = 0x7FFFFFu;  // (1 << kSlotBits) - 1
VOXGI_CONST uint kSlotFull = kSlotMask;  // entry = epoch | kSlotFull: no room, raster again
VOXGI_CONST uint kEpochCount = 511u;     // epochs 1..510, then both levels are cleared
VOXGI_CONST uint kBrickSize = 4u;        // voxels per brick side
VOXGI_CONST uint kBrickVoxels = 64u;

// The resolved grid is sparse: the list of occupied voxels (packed coordinates,
// 10 bits per axis) and, at the same index, each voxel's attributes as one uvec4
// (VoxelAttributes): nothing is stored for empty voxels and nothing costs N^3.
//   x: albedo rgb + opacity, packUnorm4x8   y: unit normal (0 when ambiguous), packSnorm4x8
//   z: emitted radiance rg, packHalf2x16    w: emitted radiance b (low half), packHalf2x16
// The compute path for small triangles (voxelize_small.comp): triangles whose
// projection reaches at most this many pixel columns and rows (at most 8: one bit
// per pixel of the box in a uvec2).
VOXGI_CONST uint kSmallTriangleSpan = 6u;
// It passes the other triangles on to the raster, compacted per group of
// kResolveGroupSize triangles: their indices at the group's own range of a buffer
// the size of the scene's indices, counted by the group's indirect command
// (DrawElementsIndirectCommand: count, instances, first index, base vertex, base
// instance), so the raster's vertex and geometry stages never see a small triangle.
// Within a group the order is the invocations' (lane by lane on llvmpipe), so the
// raster gets the triangles in the same order every run.
VOXGI_CONST uint kDrawCommandWords = 5u;
VOXGI_CONST int kVoxelHasColorsLocation = 4;      // uniform uint: 1 when the scene has them
VOXGI_CONST int kVoxelFirstIndexLocation = 1;     // uniform uint: the draw's first index
VOXGI_CONST int kVoxelTriangleCountLocation = 2;  // uniform uint: the draw's triangles
VOXGI_CONST int kVoxelCommandLocation = 3;        // uniform uint: the draw's first command
VOXGI_CONST int kVoxelDeferredAddLocation = 5;    // voxelize_deferred.comp: 0 claim, 1 add
VOXGI_CONST uint kResolveGroupSize = 64u;         // invocations per group: one brick, or 64 voxels
VOXGI_CONST uint kMaxGroupsX = 32768u;            // larger dispatches go 2D
// Waiting for a slot that another thread is claiming. A driver may cut a loop
// short: llvmpipe gives each invocation 65535 loop iterations in all (gallivm's
// LP_MAX_TGSI_LOOP_ITERATIONS, shared by every loop of the shader), and a thread
// that another holds up on a busy machine can outlast that. So the wait is short,
// and a fragment still waiting when it ends is not lost: it is recorded as it would
// have been added (VoxelDeferred) and added after the raster, when every claim is
// published (voxelize_deferred.comp). Too many for the buffer: it grows, and the
// raster runs again.
VOXGI_CONST uint kClaimSpins = 256u;
VOXGI_CONST uint kInitialDeferred = 4096u;

// What one deferred fragment adds to one voxel: the values already weighted.
struct VoxelDeferred {
  uvec4 voxel;     // x packed coordinates (10 bits per axis), y weight, zw albedo rg
  uvec4 albedoN;   // x albedo b, yzw normal xyz
  uvec4 emission;  // xyz emission rgb, w the normal's moments (x | y << 16, voxelMoments)
};

// SSBOs are limited to 128 MiB on llvmpipe: at most 2^23 - 1 voxel slots of 16
// bytes and 2^19 pool bricks of 256 bytes (entries hold slot + 1 < kSlotFull).
VOXGI_CONST uint kMaxListEntries = 8388606u;
VOXGI_CONST uint kMaxBricks = 524288u;

struct VoxelParams {
  vec4 gridOrigin;          // xyz world (scene-relative) corner, w voxel size
  vec4 gridInfo;            // x resolution, y emission fixed-point scale, z 1/scale
  uvec4 slotInfo;           // x this voxelization's epoch << kSlotBits, y bricks per axis,
                            // z the rasterizer's sub-pixel steps per pixel (2^GL_SUBPIXEL_BITS)
  vec4 samplePositions[2];  // the rasterizer's kSamplesPerFragment sample positions, xy xy
  uvec4 limits;             // x list entries (voxel slots) there is room for, y pool bricks there
                            // is room for, z slots for the resolve, w deferred records there is
                            // room for
};

// Counters the passes add to, each on its own 64-byte cache line: two cores (or GPU
// units) adding to counters on one line pass it back and forth, and every read of a
// field sharing that line waits for it. What the shaders only read is in VoxelParams.
struct VoxelStats {
  uint listCount;  // voxel slots taken: occupied voxels (may exceed limits.x)
  uint pad0[15];
  uint brickCount;  // pool bricks taken (may exceed limits.y)
  uint pad1[15];
  uint checksumSum;  // order-independent hash of the resolved bytes
  uint checksumXor;
  uint smallTriangles;  // triangles the compute path took (counted for tests only)
  uint pad2[13];
  uint deferred;      // fragments deferred (may exceed limits.w): VoxelDeferred
  uint deferredLost;  // deferred fragments whose voxel was still being claimed when added
  uint pad3[14];
};

#ifdef __cplusplus
static_assert(sizeof(VoxelParams) == 96);
static_assert(sizeof(VoxelStats) == 256);
static_assert(sizeof(VoxelDeferred) == 48);
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_VOXEL_SHARED_H
