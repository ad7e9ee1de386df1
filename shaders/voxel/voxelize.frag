#version 450 core
// Voxelization, fragment stage. The framebuffer has no attachments and 4x MSAA,
// so a fragment runs for every pixel where any of its 4 samples is covered: a
// triangle thinner than a voxel still lands (the portable stand-in for conservative
// rasterization, which llvmpipe lacks). Each fragment adds its values, weighted by
// its covered samples, into fixed-point sums with integer atomics: the result does
// not depend on fragment order, and there is no running-average drift.
// Every voxel the triangle's plane crosses inside the pixel column is written, so
// a steep surface leaves no holes along the projection axis.
// Effect-plan variants: VOXGI_NO_TEXTURES, VOXGI_NO_ALPHA, VOXGI_NO_EMISSION.
#include "scene_shared.h"
#include "voxel_shared.h"

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kMaterialBinding) readonly buffer Materials { GpuMaterial materials[]; };
layout(location = kMaterialIndexLocation) uniform int materialIndex;
layout(binding = kBaseColorUnit) uniform sampler2D baseColorTexture;

layout(std430, binding = kVoxelStatsBinding) buffer Stats { VoxelStats stats; };
layout(std430, binding = kBrickMapBinding) coherent buffer BrickMap { uint brickMap[]; };
layout(std430, binding = kBrickPoolBinding) coherent buffer BrickPool { uint pool[]; };
layout(std430, binding = kVoxelListBinding) writeonly buffer List { uint voxels[]; };
layout(std430, binding = kSlotSumsABinding) coherent buffer SumsA { uint sumsA[]; };
layout(std430, binding = kSlotSumsNBinding) coherent buffer SumsN { uint sumsN[]; };
layout(std430, binding = kSlotSumsEBinding) coherent buffer SumsE { uint sumsE[]; };

layout(location = 0) centroid in vec3 gNormal;
layout(location = 1) centroid in vec2 gUv;
layout(location = 2) flat in int gAxis;
layout(location = 3) flat in vec4 gPlane;
layout(location = 4) flat in vec2 gDepth;

ivec3 unswizzle(ivec3 p, int axis) {
  return axis == 0 ? p.zxy : (axis == 1 ? p.yzx : p);
}

// Saturating adds: once a sum would pass 2^32 - 1 it stays there.
#define ADD_SATURATING(sums, i, value)                               \
  {                                                                  \
    uint v_ = (value);                                               \
    if (v_ != 0u && atomicAdd(sums[i], v_) > 0xFFFFFFFFu - v_)       \
      atomicMax(sums[i], 0xFFFFFFFFu);                               \
  }

// Claiming an entry of the brick map or the pool, with atomicMax only (a
// compare-and-swap between lanes of one SIMD batch aimed at one address is not
// reliable on every driver). Entries hold epoch | (slot + 1); epoch | 0 means "being
// claimed". The fragment whose atomicMax raises an older epoch to this one is the
// first: it takes the next slot and publishes it. Every other fragment reads the
// entry until the slot is there (it waits only on a claim made by another thread:
// a claim made in its own batch is published before the wait).
#define CLAIM(entries, index, counter, capacity, firstAction)                              \
  uint seen = entries[index];                                                           \
  if ((seen & ~kSlotMask) != epoch || (seen & kSlotMask) == 0u) {                       \
    seen = atomicMax(entries[index], epoch);                                           \
    if ((seen & ~kSlotMask) != epoch) {                                                 \
      uint ticket = atomicAdd(counter, 1u);                                             \
      seen = epoch | ((ticket < capacity ? ticket : kSlotFull - 1u) + 1u);              \
      atomicMax(entries[index], seen);                                                  \
      if (ticket < capacity) firstAction;                                               \
    }                                                                                   \
    while ((seen & kSlotMask) == 0u) seen = atomicOr(entries[index], 0u);               \
  }

// The slot of voxel p in this epoch (kSlotFull when out of room), taking the next
// brick and voxel slots where this fragment is the first to reach them.
uint slotOf(ivec3 p) {
  uint epoch = voxel.slotInfo.x;
  uvec3 b = uvec3(p) / kBrickSize;
  uint bi = b.x + voxel.slotInfo.y * (b.y + voxel.slotInfo.y * b.z);
  uint brick;
  {
    CLAIM(brickMap, bi, stats.brickCount, stats.brickCapacity, {})
    brick = (seen & kSlotMask) - 1u;
  }
  if (brick == kSlotFull - 1u) return kSlotFull;
  uvec3 l = uvec3(p) % kBrickSize;
  uint vi = brick * kBrickVoxels + (l.x | (l.y << 2) | (l.z << 4));
  uint slot;
  {
    // The voxel's slot is its place in the list of occupied voxels.
    CLAIM(pool, vi, stats.listCount, stats.capacity,
          voxels[ticket] = uint(p.x) | (uint(p.y) << 10) | (uint(p.z) << 20))
    slot = (seen & kSlotMask) - 1u;
  }
  return slot == kSlotFull - 1u ? kSlotFull : slot;
}

uint fixedPoint(float x) { return uint(clamp(x, 0.0, 1.0) * float(kFixedOne) + 0.5); }

void main() {
  GpuMaterial m = materials[materialIndex];
  vec4 base = m.baseColor;
#ifndef VOXGI_NO_TEXTURES
  if ((m.flags & kMaterialHasTexture) != 0u) base *= texture(baseColorTexture, gUv);
#endif
#ifndef VOXGI_NO_ALPHA
  if ((m.flags & kMaterialAlphaMask) != 0u && base.a < m.params.z) discard;
#endif

  uint weight = uint(bitCount(gl_SampleMaskIn[0]));
  if (weight == 0u) return;
  int res = int(voxel.gridInfo.x);

  // Depth span of the plane over this pixel, clipped to the triangle's own span.
  vec2 uv = gl_FragCoord.xy;
  float zc = gPlane.x + gPlane.y * uv.x + gPlane.z * uv.y;
  float half_ = 0.5 * (abs(gPlane.y) + abs(gPlane.z));
  float z0 = max(zc - half_, gDepth.x);
  float z1 = min(zc + half_, gDepth.y);
  int k0 = clamp(int(floor(z0)), 0, res - 1);
  int k1 = clamp(int(floor(z1)), 0, res - 1);

  vec3 n = normalize(gNormal);
  if (any(isnan(n))) n = vec3(0.0);
  uint albedo[3] = uint[3](fixedPoint(base.r), fixedPoint(base.g), fixedPoint(base.b));
  uint normal[3] = uint[3](fixedPoint(n.x * 0.5 + 0.5), fixedPoint(n.y * 0.5 + 0.5),
                           fixedPoint(n.z * 0.5 + 0.5));
#ifdef VOXGI_NO_EMISSION
  vec3 e = vec3(0.0);
#else
  vec3 e = m.emission.rgb * voxel.gridInfo.y;  // scaled so the scene's largest is 1
#endif
  uint emission[3] = uint[3](fixedPoint(e.r), fixedPoint(e.g), fixedPoint(e.b));

  ivec2 pixel = ivec2(uv);
  bool emits = emission[0] + emission[1] + emission[2] != 0u;
  for (int k = k0; k <= k1; ++k) {
    ivec3 p = unswizzle(ivec3(pixel, k), gAxis);
    uint slot = slotOf(p);
    if (slot == kSlotFull) continue;  // the list overflowed: the pass runs again
    uint i = slot * 4u;
    ADD_SATURATING(sumsA, i + 0u, albedo[0] * weight);
    ADD_SATURATING(sumsA, i + 1u, albedo[1] * weight);
    ADD_SATURATING(sumsA, i + 2u, albedo[2] * weight);
    ADD_SATURATING(sumsA, i + 3u, weight);
    ADD_SATURATING(sumsN, i + 0u, normal[0] * weight);
    ADD_SATURATING(sumsN, i + 1u, normal[1] * weight);
    ADD_SATURATING(sumsN, i + 2u, normal[2] * weight);
    if (emits) {
      ADD_SATURATING(sumsE, i + 0u, emission[0] * weight);
      ADD_SATURATING(sumsE, i + 1u, emission[1] * weight);
      ADD_SATURATING(sumsE, i + 2u, emission[2] * weight);
    }
  }
}
