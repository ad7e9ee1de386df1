// Tangent-space normal maps (glTF normalTexture), written once for GLSL and C++
// (see shared_fn.h): the raster and G-buffer fragment shaders, the path tracer on
// both devices (through texture_shared.h's mappedNormal) and rtgi's reflections
// bend their shading normal with these two functions.
//
// The back-facing rule. A mapped normal can face away from the viewer (a steep bump
// seen at a grazing angle), or from the side of the surface the viewer is on; shading
// with it would give black pixels (no light reaches a normal facing away) or NaN.
// So wherever a shading normal n_s is used, with wo the unit direction to the viewer
// (camera or previous path vertex) on the geometric normal's side:
//   if dot(n_s, wo) < kMinShadingCos, n_s moves towards wo in their common plane until
//   dot(n_s, wo) = kMinShadingCos before normalization (bendShadingNormal): the least
//   change that keeps the viewer in the shading hemisphere; the rest of the frame is
//   kept.
// Light through the surface (light leaks) is the other half: a light or a sampled
// direction below the *geometric* normal never contributes, whatever the shading
// normal says (the path tracer rejects such samples; raster and rtgi test the
// geometric normal of the triangle too).
// Tests: tests/render/normal_maps_gltest.cpp.
#ifndef VOXGI_NORMAL_MAP_SHARED_H
#define VOXGI_NORMAL_MAP_SHARED_H

#include "shared_fn.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// The least cosine between a bent shading normal and the direction to the viewer,
// before normalization.
VOXGI_CONST float kMinShadingCos = 0.01f;

// Unit normal n perturbed by a normal-map texel (linear, [0, 1] per channel) in the
// frame of `tangent` (xyz the direction u grows in, w the handedness: bitangent =
// w * cross(n, tangent)), with glTF's normalTexture.scale on the map's x and y. The
// tangent is first made perpendicular to n (Gram-Schmidt), since interpolation
// across a triangle leaves it slightly off. A degenerate frame or texel returns n.
VOXGI_FN vec3 perturbNormal(vec3 n, vec4 tangent, vec3 texel, float scale) {
  vec3 tn = texel * 2.0f - 1.0f;
  tn = vec3(tn.x * scale, tn.y * scale, tn.z);
  vec3 t = vec3(tangent) - n * dot(n, vec3(tangent));
  float tl = length(t);
  if (!(tl > 1e-6f)) return n;
  t = t / tl;
  vec3 b = cross(n, t) * (tangent.w < 0.0f ? -1.0f : 1.0f);
  vec3 m = t * tn.x + b * tn.y + n * tn.z;
  float ml = length(m);
  if (!(ml > 1e-6f) || !(ml < 1e30f)) return n;
  return m / ml;
}

// rtgi's G-buffer keeps the shading (mapped) normal; the surface's own normal, which
// the leak rule needs, travels in one spare 16-bit float (the emission target's w):
// octahedral coordinates on a 64 x 64 grid (within 3.8 degrees), as the cell
// index + 1 in +-[1, 2048], integers a half float holds exactly; 0 means "not packed".
VOXGI_FN float packSurfaceNormal(vec3 n) {
  n = n / max(abs(n.x) + abs(n.y) + abs(n.z), 1e-20f);
  vec2 e = vec2(n.x, n.y);
  if (n.z < 0.0f)
    e = vec2((1.0f - abs(n.y)) * (n.x >= 0.0f ? 1.0f : -1.0f),
             (1.0f - abs(n.x)) * (n.y >= 0.0f ? 1.0f : -1.0f));
  uint ix = uint(clamp(floor((e.x * 0.5f + 0.5f) * 64.0f), 0.0f, 63.0f));
  uint iy = uint(clamp(floor((e.y * 0.5f + 0.5f) * 64.0f), 0.0f, 63.0f));
  uint idx = iy * 64u + ix;
  return idx < 2048u ? float(idx + 1u) : -float(idx - 2047u);
}

VOXGI_FN vec3 unpackSurfaceNormal(float v) {
  uint idx = v > 0.0f ? uint(v) - 1u : uint(-v) + 2047u;
  vec2 e = (vec2(float(idx % 64u), float(idx / 64u)) + 0.5f) / 64.0f * 2.0f - 1.0f;
  vec3 n = vec3(e.x, e.y, 1.0f - abs(e.x) - abs(e.y));
  if (n.z < 0.0f) {
    float x = n.x;
    n.x = (1.0f - abs(n.y)) * (x >= 0.0f ? 1.0f : -1.0f);
    n.y = (1.0f - abs(x)) * (n.y >= 0.0f ? 1.0f : -1.0f);
  }
  return normalize(n);
}

// The back-facing rule above: ns (unit) bent so that the viewer at unit direction
// wo stays above its hemisphere.
VOXGI_FN vec3 bendShadingNormal(vec3 ns, vec3 wo) {
  float c = dot(ns, wo);
  if (c >= kMinShadingCos) return ns;
  return normalize(ns + (kMinShadingCos - c) * wo);
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_NORMAL_MAP_SHARED_H
