// Texture reads (base colour, emission, metallic-roughness) and alpha masks, written
// once for GLSL and C++ (see shared_fn.h): the path tracer on both devices (through
// pathtrace_shading.h) and rtgi's reflections of exact triangles read texels with
// these. Each device brings its access to the tables through macros: the shader
// defines them before the include, C++ gets them below.
//   VOXGI_EMISSIVE(i)  the i-th GpuPtEmissive of the alias table (pathtrace_shading.h);
//   VOXGI_TEXEL(i)     the i-th packed RGBA8 texel of all textures;
//   VOXGI_TEXTURE(i)   the i-th texture's table entry (optional: without it, only
//                      the reads that take an entry are compiled);
//   VOXGI_TABLES_PARAM / VOXGI_TABLES_ARG  how the tables reach a function (C++: a
//                      PtTables reference; GLSL: nothing, they are buffers).
// Twin test: tests/render/shading_twin_gltest.cpp.
#ifndef VOXGI_TEXTURE_SHARED_H
#define VOXGI_TEXTURE_SHARED_H

#include "normal_map_shared.h"
#include "pathtrace_shared.h"
#include "sampling_shared.h"
#include "scene_shared.h"
#include "shared_fn.h"

#ifdef __cplusplus
namespace voxgi::gpu {
using glm::isinf;
using glm::isnan;
using glm::smoothstep;
// The CPU device's tables.
struct PtTables {
  const GpuPtEmissive* emissive = nullptr;
  const uint* texels = nullptr;
  const uvec4* textures = nullptr;  // the texture table: one entry per texture
};
#define VOXGI_TABLES_PARAM const PtTables &tables,
#define VOXGI_TABLES_ARG tables,
#define VOXGI_EMISSIVE(i) tables.emissive[i]
#define VOXGI_TEXEL(i) tables.texels[i]
#define VOXGI_TEXTURE(i) tables.textures[i]
#endif

// --- textures -----------------------------------------------------------------------
// A texture's table entry t = (first texel, width, height, flags): kTextureSrgb,
// kTextureNearest and each axis's wrap mode (scene_shared.h).
// One texel of texture t, linear: colour textures (kTextureSrgb) are decoded from
// sRGB, data textures read as they are.
VOXGI_FN vec4 srgbTexel(VOXGI_TABLES_PARAM uvec4 t, ivec2 p) {
  vec4 c = unpackUnorm4x8(VOXGI_TEXEL(t.x + uint(p.y) * t.y + uint(p.x)));
  if ((t.w & kTextureSrgb) == 0u) return c;
  vec3 rgb = vec3(c);
  vec3 lo = rgb / 12.92f;
  vec3 hi = pow((rgb + 0.055f) / 1.055f, vec3(2.4f));
  return vec4(c.r <= 0.04045f ? lo.r : hi.r, c.g <= 0.04045f ? lo.g : hi.g,
              c.b <= 0.04045f ? lo.b : hi.b, c.a);
}

// One texture coordinate brought into the range its wrap mode repeats over: [0, 1)
// for REPEAT, [0, 2) for MIRRORED_REPEAT (a period is the texture and its mirror
// image), [0, 1] for CLAMP_TO_EDGE. Keeps the precision of large coordinates.
VOXGI_FN float wrapCoordinate(float u, uint mode) {
  if (mode == kTextureClampToEdge) return clamp(u, 0.0f, 1.0f);
  if (mode == kTextureMirroredRepeat) return 2.0f * fract(0.5f * u);
  return fract(u);
}

// Texel index i of an axis of n texels under `mode`, as GL wraps it; i is in
// [-1, 2n], what sampleTexture makes of a wrapped coordinate.
VOXGI_FN int wrapTexel(int i, int n, uint mode) {
  if (mode == kTextureClampToEdge) return clamp(i, 0, n - 1);
  if (mode == kTextureMirroredRepeat) {
    int m = i < 0 ? i + 2 * n : (i >= 2 * n ? i - 2 * n : i);
    return m >= n ? 2 * n - 1 - m : m;
  }
  return i < 0 ? i + n : (i >= n ? i - n : i);
}

// Texture t at uv over linear (decoded) texels, wrapped per axis as the file's
// sampler says (as the raster's GL sampler does); bilinear, or the nearest texel
// when its magnification filter is NEAREST. No mipmaps: paths jittered over the
// pixel average the footprint.
VOXGI_FN vec4 sampleTexture(VOXGI_TABLES_PARAM uvec4 t, vec2 uv) {
  ivec2 size = ivec2(int(t.y), int(t.z));
  if (isnan(uv.x) || isinf(uv.x)) uv.x = 0.0f;
  if (isnan(uv.y) || isinf(uv.y)) uv.y = 0.0f;
  uint ws = (t.w >> kTextureWrapSShift) & 3u;
  uint wt = (t.w >> kTextureWrapTShift) & 3u;
  // In texel units, texel centres at integers: [-0.5, size - 0.5) for REPEAT.
  vec2 x = vec2(wrapCoordinate(uv.x, ws), wrapCoordinate(uv.y, wt)) * vec2(size) - 0.5f;
  if ((t.w & kTextureNearest) != 0u) {
    ivec2 p = ivec2(floor(x + 0.5f));
    return srgbTexel(VOXGI_TABLES_ARG t,
                     ivec2(wrapTexel(p.x, size.x, ws), wrapTexel(p.y, size.y, wt)));
  }
  vec2 f = x - floor(x);
  ivec2 i0 = ivec2(floor(x));
  ivec2 a = ivec2(wrapTexel(i0.x, size.x, ws), wrapTexel(i0.y, size.y, wt));
  ivec2 b = ivec2(wrapTexel(i0.x + 1, size.x, ws), wrapTexel(i0.y + 1, size.y, wt));
  return mix(
      mix(srgbTexel(VOXGI_TABLES_ARG t, a), srgbTexel(VOXGI_TABLES_ARG t, ivec2(b.x, a.y)), f.x),
      mix(srgbTexel(VOXGI_TABLES_ARG t, ivec2(a.x, b.y)), srgbTexel(VOXGI_TABLES_ARG t, b), f.x),
      f.y);
}

// --- alpha masks ------------------------------------------------------------------------
// A number in [0, 1) for the point at barycentric coordinates bc of triangle tri, a
// hash of the two: as good as a uniform draw for each ray that meets the surface
// (rays meet it at points that differ in their low bits), and the same for the
// same point. The threshold of a blended material's alpha (alphaStops); hashed
// alpha testing (Wyman and McGuire 2017, "Hashed alpha testing") at the hit point's
// own precision instead of a grid, since samples accumulate.
VOXGI_FN float alphaHash(uint tri, vec2 bc) {
  uint h = pcgHash(tri ^ pcgHash(floatBitsToUint(bc.x) ^ pcgHash(floatBitsToUint(bc.y))));
  return float(h >> 8u) * (1.0f / 16777216.0f);
}

// Whether a ray stops at a hit at uv on material m: an alpha-masked material (glTF
// MASK) lets rays through where base alpha x texture alpha < its cutoff, as the
// raster modes discard those fragments; a blended one (BLEND) where alpha <=
// `threshold`, a uniform number in [0, 1) for this hit (alphaHash): the ray stops
// with probability alpha, the surface's coverage. `texture` is m's table entry
// (read only when `textured` and m has a texture).
VOXGI_FN bool alphaStops(VOXGI_TABLES_PARAM GpuMaterial m, bool textured, uvec4 texture, vec2 uv,
                         float threshold) {
  if ((m.flags & (kMaterialAlphaMask | kMaterialAlphaBlend)) == 0u) return true;
  float a = m.baseColor.a;
  if (textured && (m.flags & kMaterialHasTexture) != 0u)
    a *= sampleTexture(VOXGI_TABLES_ARG texture, uv).a;
  return (m.flags & kMaterialAlphaBlend) != 0u ? a > threshold : a >= m.alphaCutoff;
}

#ifdef VOXGI_TEXTURE
// --- materials ------------------------------------------------------------------------
// The texture coordinates of the slot whose channel-1 bit is `uv2Bit`
// (kMaterial*Uv2): uv2 (channel 1) where m sets it, uv (channel 0) otherwise.
VOXGI_FN vec2 slotUv(GpuMaterial m, uint uv2Bit, vec2 uv, vec2 uv2) {
  return (m.flags & uv2Bit) != 0u ? uv2 : uv;
}

// Material m as seen at texture coordinates uv (channel 0) and uv2 (channel 1): its
// base colour, metallic, roughness and emission times whichever of its textures it
// has (glTF: metallic in the blue channel, roughness in green), each read at its
// own channel. Returns m unchanged when it has none.
VOXGI_FN GpuMaterial texturedMaterial(VOXGI_TABLES_PARAM GpuMaterial m, vec2 uv, vec2 uv2) {
  if ((m.flags & kMaterialHasTexture) != 0u)
    m.baseColor *= sampleTexture(VOXGI_TABLES_ARG VOXGI_TEXTURE(m.texture), uv);
  if ((m.flags & kMaterialHasMetallicRoughnessTexture) != 0u) {
    vec4 mr = sampleTexture(VOXGI_TABLES_ARG VOXGI_TEXTURE(m.metallicRoughnessTexture),
                            slotUv(m, kMaterialMetallicRoughnessUv2, uv, uv2));
    m.metallic *= mr.b;
    m.roughness *= mr.g;
  }
  if ((m.flags & kMaterialHasEmissiveTexture) != 0u) {
    vec4 e = sampleTexture(VOXGI_TABLES_ARG VOXGI_TEXTURE(m.emissiveTexture),
                           slotUv(m, kMaterialEmissiveUv2, uv, uv2));
    m.emission *= vec3(e);
  }
  return m;
}

// The shading normal of material m at texture coordinates uv, uv2 (as above): unit
// n perturbed by its normal map in the frame of `tangent` (normal_map_shared.h); n
// itself without a normal map.
VOXGI_FN vec3 mappedNormal(VOXGI_TABLES_PARAM GpuMaterial m, vec3 n, vec4 tangent, vec2 uv,
                           vec2 uv2) {
  if ((m.flags & kMaterialHasNormalTexture) == 0u) return n;
  vec4 texel = sampleTexture(VOXGI_TABLES_ARG VOXGI_TEXTURE(m.normalTexture),
                             slotUv(m, kMaterialNormalUv2, uv, uv2));
  return perturbNormal(n, tangent, vec3(texel), m.normalScale);
}
#endif

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_TEXTURE_SHARED_H
