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

layout(binding = 0, r32ui) uniform coherent uimage3D sums[kSumChannels];
layout(std430, binding = kVoxelStatsBinding) buffer Stats { VoxelStats stats; };
layout(std430, binding = kVoxelListBinding) writeonly buffer List { uint voxels[]; };

layout(location = 0) centroid in vec3 gNormal;
layout(location = 1) centroid in vec2 gUv;
layout(location = 2) flat in int gAxis;
layout(location = 3) flat in vec4 gPlane;
layout(location = 4) flat in vec2 gDepth;

ivec3 unswizzle(ivec3 p, int axis) {
  return axis == 0 ? p.zxy : (axis == 1 ? p.yzx : p);
}

// Saturating add: once a sum would pass 2^32 - 1 it stays there. Returns the old value.
uint addSaturating(int channel, ivec3 p, uint value) {
  if (value == 0u) return 1u;
  uint old = imageAtomicAdd(sums[channel], p, value);
  if (old > 0xFFFFFFFFu - value) imageAtomicMax(sums[channel], p, 0xFFFFFFFFu);
  return old;
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
  for (int k = k0; k <= k1; ++k) {
    ivec3 p = unswizzle(ivec3(pixel, k), gAxis);
    // Constant indices only: image arrays indexed by a loop variable are not
    // reliable on every driver.
    addSaturating(0, p, albedo[0] * weight);
    addSaturating(1, p, albedo[1] * weight);
    addSaturating(2, p, albedo[2] * weight);
    addSaturating(3, p, normal[0] * weight);
    addSaturating(4, p, normal[1] * weight);
    addSaturating(5, p, normal[2] * weight);
    addSaturating(6, p, emission[0] * weight);
    addSaturating(7, p, emission[1] * weight);
    addSaturating(8, p, emission[2] * weight);
    // The first fragment to reach a voxel lists it: later passes visit only
    // listed voxels, so nothing costs N^3.
    if (addSaturating(9, p, weight) == 0u) {
      uint slot = atomicAdd(stats.listCount, 1u);
      if (slot < stats.capacity) voxels[slot] = uint(p.x) | (uint(p.y) << 10) | (uint(p.z) << 20);
    }
  }
}
