#version 450 core
// rtgi stage "shadows": direct light at each pixel's surface (rtgi_direct_light.glsl:
// punctual lights exactly, emitters through one shadow ray each frame), with shadow
// rays against the exact triangles (RTGI_BVH: the BVH, rtgi_bvh.glsl), or through
// the octree's voxels (without it: --voxel-rays, or an animated scene). Voxels are
// coarser than the geometry: they shadow too much near contacts and at grazing
// angles, which accumulation never removes; the triangles give the path tracer's
// shadows. Mirrors take no highlight here: their reflected ray sees the light.
// RTGI_HIGHLIGHT_MIS: the specular stage's lobe rays see emitters too, and the
// highlights of glossy pixels are shared with them (rtgi_direct_light.glsl);
// RTGI_HIGHLIGHT_SAMPLED (no specular stage that shares them): the light sample
// carries them whole.
// Effect-plan variants (scene/effects.h): VOXGI_NO_SHADOWS traces no shadow ray (the
// renderer then names the stage "direct"); VOXGI_NO_EMISSION leaves emitters out.
// Scene variants (RtgiPass): RTGI_LIGHTS when there are punctual lights,
// RTGI_EMITTERS_EXACT (few emitters) or RTGI_EMITTERS_SAMPLED (many) when there are
// emitters; RTGI_RESTIR_INITIAL and RTGI_RESTIR, the two dispatches of reservoir
// resampling of many emitters (rtgi_restir.glsl); RTGI_EMITTER_TILES, candidates taken
// from the pixel's light tile (rtgi_light_tiles.comp) where the tree draws among all
// the emitters at once. A software rasterizer runs both sides of every
// branch under a lane mask, and a loop's body at least once: code for what the scene lacks would
// cost as much as code that runs, so it is compiled out.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "octree_light.glsl"
#define RTGI_PIXEL_LIST
#include "rtgi_common.glsl"
#ifdef RTGI_BVH
#include "rtgi_bvh.glsl"
#endif

layout(local_size_x = kRtgiTraceGroup) in;

layout(binding = kDirectImage, rgba16f) uniform writeonly image2D directOut;

float shadowRay(vec3 o, vec3 l, float dist, bool toEmitter, float slack) {
#ifdef VOXGI_NO_SHADOWS
  return 1.0;
#elif defined(RTGI_BVH)
  return bvhVisible(o, l, dist, toEmitter, slack);
#else
  // Short of an emitter by its voxels, which would otherwise hide it.
  return octreeVisible(o, l, dist, 0.0, toEmitter ? kSurfaceOffsetVoxels : 0.0);
#endif
}

#include "rtgi_direct_light.glsl"
#ifdef RTGI_EMITTER_TILES
// The light tiles (rtgi_light_tiles.comp): for each 8x8 tile of pixels,
// kLightTileSamples emitters drawn from its distribution, each as its place among
// the light tree's leaves and its probability.
layout(std430, binding = kRtgiReservoirBinding) readonly buffer LightTiles { uvec2 lightTiles[]; };
// The pixel whose tile the candidates come from; main sets it.
ivec2 tilePixel = ivec2(0);

// One of the emitters drawn for the pixel's tile, taken at random (uniform number u):
// its index, its probability under the tile's distribution in pmf and its leaf node
// in `leaf`; -1 (pmf 0) where no emitter can light the tile. Each of the tile's
// emitters was drawn from that distribution, so the one taken is too, whichever
// entry it is (the candidates of a pixel, and of its tile's pixels, may repeat one:
// resampled importance sampling stays unbiased for candidates that depend on each
// other, as long as each is drawn from the distribution its weight divides by).
int pickTileEmitter(float u, out float pmf, out GpuLightNode leaf) {
  uint tilesX = (rtgi.width + kLightTileSize - 1u) / kLightTileSize;
  uint tile = uint(tilePixel.y) / kLightTileSize * tilesX + uint(tilePixel.x) / kLightTileSize;
  uint slot = min(uint(u * float(kLightTileSamples)), kLightTileSamples - 1u);
  uvec2 entry = lightTiles[tile * kLightTileSamples + slot];
  pmf = uintBitsToFloat(entry.y);
  if (!(pmf > 0.0)) return -1;
  leaf = lightTree[int(lightTree[0].info.z) + int(entry.x)];
  return int(leaf.info.y);
}
#endif
#if defined(RTGI_RESTIR) || defined(RTGI_RESTIR_INITIAL)
#include "rtgi_restir.glsl"
#endif

void main() {
  ivec2 px;
  if (!tracePixel(px)) return;
  Pixel p = loadPixel(px);
#ifdef RTGI_RESTIR_INITIAL
  // The first of the two dispatches of reservoir resampling (rtgi_restir.glsl).
  seedPixel(px, 4u);
  if (p.covered)
    restirInitial(px, p);
  else
    reservoirs[reservoirIndex(px)] = packReservoir(-1, 0.0, 0.0);
  return;
#endif
  vec3 result = vec3(0.0);
  if (p.covered) {
    seedPixel(px, 1u);
#ifdef RTGI_EMITTER_TILES
    tilePixel = px;
#endif
    Surface s = p.s;
    if (p.roughness < kMirrorRoughness) s.f0 = vec3(0.0);
#ifdef RTGI_HIGHLIGHT_MIS
    // The specular stage's lobe ray shares this pixel's highlights.
    highlightMis = p.roughness >= kMirrorRoughness && isSpecular(p.metallic, p.roughness);
#elif defined(RTGI_HIGHLIGHT_SAMPLED)
    highlightSampled = true;
#endif
    // The surface's own normal where a normal map tilts s.n (else 0: no test).
    vec3 ng = surfaceNormal(px);
#ifdef RTGI_BVH
    vec3 o = s.p + (ng != vec3(0.0) ? ng : s.n) * bvhEpsilon();
#else
    vec3 o = surfaceRayOrigin(px, s);
#endif
#ifdef RTGI_RESTIR
    result = punctualDirect(s, o, ng) + restirDirect(px, s, o, ng);
#else
    result = directLight(s, o, ng);
#endif
  }
  imageStore(directOut, px, vec4(result, 1.0));
}
