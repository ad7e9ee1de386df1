// Voxelization: what one covered pixel of a triangle adds to the grid. Shared by
// the raster's fragment stage and the compute path for small triangles, so both
// write the same sums the same way. The includer declares the VoxelBlock uniform
// block (`voxel`).
//
// Each fragment adds its values, weighted by its covered samples, into fixed-point
// sums with integer atomics: the result does not depend on fragment order, and
// there is no running-average drift. Every voxel the triangle's plane crosses
// inside the pixel column is written, so a steep surface leaves no holes along the
// projection axis.

layout(std430, binding = kVoxelStatsBinding) buffer Stats { VoxelStats stats; };
layout(std430, binding = kBrickMapBinding) coherent buffer BrickMap { uint brickMap[]; };
layout(std430, binding = kBrickPoolBinding) coherent buffer BrickPool { uint pool[]; };
layout(std430, binding = kVoxelListBinding) writeonly buffer List { uint voxels[]; };
layout(std430, binding = kSlotSumsABinding) coherent buffer SumsA { uint sumsA[]; };
layout(std430, binding = kSlotSumsNBinding) coherent buffer SumsN { uint sumsN[]; };
layout(std430, binding = kSlotSumsEBinding) coherent buffer SumsE { uint sumsE[]; };
layout(std430, binding = kVoxelDeferredBinding) buffer Deferred { VoxelDeferred deferred[]; };

uint voxelPacked(ivec3 p) { return uint(p.x) | (uint(p.y) << 10) | (uint(p.z) << 20); }

ivec3 voxelUnswizzle(ivec3 p, int axis) { return axis == 0 ? p.zxy : (axis == 1 ? p.yzx : p); }

// Saturating adds: once a sum would pass 2^32 - 1 it stays there.
#define ADD_SATURATING(sums, i, value)                                                          \
  {                                                                                             \
    uint v_ = (value);                                                                          \
    if (v_ != 0u && atomicAdd(sums[i], v_) > 0xFFFFFFFFu - v_) atomicMax(sums[i], 0xFFFFFFFFu); \
  }

// Claiming an entry of the brick map or the pool, with atomicMax only (a
// compare-and-swap between lanes of one SIMD batch aimed at one address is not
// reliable on every driver). Entries hold epoch | (slot + 1); epoch | 0 means "being
// claimed". The invocation whose atomicMax raises an older epoch to this one is the
// first: it takes the next slot and publishes it. Every other one reads the entry
// until the slot is there, at most kClaimSpins times (it waits only on a claim made
// by another thread: a claim made in its own batch is published before the wait);
// after that the slot stays 0 and the caller defers the fragment (voxel_shared.h).
#ifndef VOXGI_CLAIM_SPINS
#define VOXGI_CLAIM_SPINS kClaimSpins
#endif
#define CLAIM(entries, index, counter, capacity, firstAction)                             \
  uint seen = entries[index];                                                             \
  if ((seen & ~kSlotMask) != epoch || (seen & kSlotMask) == 0u) {                         \
    seen = atomicMax(entries[index], epoch);                                              \
    if ((seen & ~kSlotMask) != epoch) {                                                   \
      uint ticket = atomicAdd(counter, 1u);                                               \
      seen = epoch | ((ticket < capacity ? ticket : kSlotFull - 1u) + 1u);                \
      atomicMax(entries[index], seen);                                                    \
      if (ticket < capacity) firstAction;                                                 \
    }                                                                                     \
    for (uint spin_ = 0u; spin_ < VOXGI_CLAIM_SPINS && (seen & kSlotMask) == 0u; ++spin_) \
      seen = atomicOr(entries[index], 0u);                                                \
  }

// voxelSlot(): the voxel is being claimed by a thread that has not published its
// slot yet.
const uint kSlotPending = 0xFFFFFFFFu;

// The slot of voxel p in this epoch (kSlotFull when out of room, kSlotPending when
// another thread's claim is not published yet), taking the next brick and voxel
// slots where this invocation is the first to reach them.
uint voxelSlot(ivec3 p) {
  uint epoch = voxel.slotInfo.x;
  uvec3 b = uvec3(p) / kBrickSize;
  uint bi = b.x + voxel.slotInfo.y * (b.y + voxel.slotInfo.y * b.z);
  uint brick;
  {
    CLAIM(brickMap, bi, stats.brickCount, voxel.limits.y, {})
    if ((seen & kSlotMask) == 0u) return kSlotPending;
    brick = (seen & kSlotMask) - 1u;
  }
  if (brick == kSlotFull - 1u) return kSlotFull;
  uvec3 l = uvec3(p) % kBrickSize;
  uint vi = brick * kBrickVoxels + (l.x | (l.y << 2) | (l.z << 4));
  uint slot;
  {
    // The voxel's slot is its place in the list of occupied voxels.
    CLAIM(pool, vi, stats.listCount, voxel.limits.x, voxels[ticket] = voxelPacked(p))
    if ((seen & kSlotMask) == 0u) return kSlotPending;
    slot = (seen & kSlotMask) - 1u;
  }
  return slot == kSlotFull - 1u ? kSlotFull : slot;
}

// Adds one fragment's weighted values to the sums of `slot`. `m`: the normal's
// second moments along x and y (voxelMoments), kept in the free lanes of the normal
// and emission sums.
void voxelAddToSlot(uint slot, uint weight, uvec3 a, uvec3 n, uvec3 e, uvec2 m) {
  uint i = slot * 4u;
  ADD_SATURATING(sumsA, i + 0u, a.r);
  ADD_SATURATING(sumsA, i + 1u, a.g);
  ADD_SATURATING(sumsA, i + 2u, a.b);
  ADD_SATURATING(sumsA, i + 3u, weight);
  ADD_SATURATING(sumsN, i + 0u, n.x);
  ADD_SATURATING(sumsN, i + 1u, n.y);
  ADD_SATURATING(sumsN, i + 2u, n.z);
  ADD_SATURATING(sumsN, i + 3u, m.x);
  ADD_SATURATING(sumsE, i + 3u, m.y);
  if (e != uvec3(0u)) {
    ADD_SATURATING(sumsE, i + 0u, e.r);
    ADD_SATURATING(sumsE, i + 1u, e.g);
    ADD_SATURATING(sumsE, i + 2u, e.b);
  }
}

// The unit normal's squares along x and y in kMomentOne steps (z's follows from
// their sum): over a voxel's fragments, the axis its normals lie along even where
// they cancel (both sides of a thin wall), which the resolve keeps for such voxels.
uvec2 voxelMoments(vec3 n) {
  return uvec2(uint(clamp(n.x * n.x, 0.0, 1.0) * float(kMomentOne) + 0.5),
               uint(clamp(n.y * n.y, 0.0, 1.0) * float(kMomentOne) + 0.5));
}

uint voxelFixedPoint(float x) { return uint(clamp(x, 0.0, 1.0) * float(kFixedOne) + 0.5); }

// Adds one fragment: pixel (u, v) of the swizzled projection along `axis`, the
// triangle's plane z = plane.x + plane.y u + plane.z v and z range `depth`, linear
// albedo, unit normal (or 0), emission already scaled to [0, 1], and `weight` covered
// samples (1..4).
void voxelAddFragment(ivec2 pixel, int axis, vec4 plane, vec2 depth, vec3 albedo, vec3 n, vec3 e,
                      uint weight) {
  int res = int(voxel.gridInfo.x);
  // Depth span of the plane over this pixel, clipped to the triangle's own span.
  vec2 uv = vec2(pixel) + 0.5;
  float zc = plane.x + plane.y * uv.x + plane.z * uv.y;
  float half_ = 0.5 * (abs(plane.y) + abs(plane.z));
  float z0 = max(zc - half_, depth.x);
  float z1 = min(zc + half_, depth.y);
  int k0 = clamp(int(floor(z0)), 0, res - 1);
  int k1 = clamp(int(floor(z1)), 0, res - 1);

  uvec3 a = uvec3(voxelFixedPoint(albedo.r), voxelFixedPoint(albedo.g), voxelFixedPoint(albedo.b));
  uvec3 nf = uvec3(voxelFixedPoint(n.x * 0.5 + 0.5), voxelFixedPoint(n.y * 0.5 + 0.5),
                   voxelFixedPoint(n.z * 0.5 + 0.5));
  uvec3 ef = uvec3(voxelFixedPoint(e.r), voxelFixedPoint(e.g), voxelFixedPoint(e.b));
  a *= weight;
  nf *= weight;
  ef *= weight;
  uvec2 moments = voxelMoments(n) * weight;
  for (int k = k0; k <= k1; ++k) {
    ivec3 p = voxelUnswizzle(ivec3(pixel, k), axis);
#ifdef VOXGI_DEFER_ALL  // tests: the deferred pass adds every fragment
    uint slot = kSlotPending;
#else
    uint slot = voxelSlot(p);
#endif
    if (slot == kSlotFull) continue;  // the list overflowed: the pass runs again
    if (slot == kSlotPending) {
      // Added after the raster (voxelize_deferred.comp); no room: the pass grows the
      // buffer and runs again.
      uint d = atomicAdd(stats.deferred, 1u);
      if (d < voxel.limits.w)
        deferred[d] = VoxelDeferred(uvec4(voxelPacked(p), weight, a.rg), uvec4(a.b, nf),
                                    uvec4(ef, moments.x | (moments.y << 16)));
      continue;
    }
    voxelAddToSlot(slot, weight, a, nf, ef, moments);
  }
}
