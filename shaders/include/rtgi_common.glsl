// What the rtgi per-pixel stages share: parameters, the G-buffer, the surface at a
// pixel and its random stream. Include after scene_shared.h, lighting.glsl,
// sampling.glsl and octree.glsl.
#ifndef VOXGI_RTGI_COMMON_GLSL
#define VOXGI_RTGI_COMMON_GLSL

#include "rtgi_shared.h"
#include "normal_map_shared.h"
#include "interleave_shared.h"

layout(std140, binding = kRtgiParamsBinding) uniform RtgiBlock { RtgiParams rtgi; };
layout(binding = kGPositionUnit) uniform sampler2D gPosition;
layout(binding = kGNormalUnit) uniform sampler2D gNormal;
layout(binding = kGAlbedoUnit) uniform sampler2D gAlbedo;
layout(binding = kGEmissionUnit) uniform sampler2D gEmission;

struct Pixel {
  bool covered;
  Surface s;
  float roughness;
  float metallic;
  vec3 base;
};

Pixel loadPixel(ivec2 px) {
  Pixel p;
  vec4 pos = texelFetch(gPosition, px, 0);
  vec4 nr = texelFetch(gNormal, px, 0);
  vec4 am = texelFetch(gAlbedo, px, 0);
  p.covered = pos.w > 0.5;
  p.roughness = clamp(nr.w, 0.0, 1.0);
  p.metallic = am.a;
  p.base = am.rgb;
  p.s.p = pos.xyz;
  p.s.n = normalize(nr.xyz);
  p.s.v = normalize(rtgi.camera.xyz - pos.xyz);
  p.s.diffuse = am.rgb * (1.0 - am.a);
  p.s.f0 = metallicF0(am.rgb, am.a);
  p.s.alpha = p.roughness * p.roughness;
  p.s.specular = isLambertian(p.metallic, p.roughness) ? 0.0 : 1.0;
  return p;
}

// The surface's own normal at px where the G-buffer packed it (scenes with normal
// maps: normal_map_shared.h), else 0.
vec3 surfaceNormal(ivec2 px) {
  float code = texelFetch(gEmission, px, 0).w;
  return code != 0.0 ? unpackSurfaceNormal(code) : vec3(0.0);
}

// Whether direction d leaves the surface at px from below its own normal, which the
// G-buffer packs in scenes with normal maps (normal_map_shared.h): light and rays
// there do not count, whatever the mapped normal says (the leak rule). Always false
// where nothing is packed.
bool belowSurface(ivec2 px, vec3 d) {
  float code = texelFetch(gEmission, px, 0).w;
  return code != 0.0 && dot(d, unpackSurfaceNormal(code)) <= 0.0;
}

// A stream per pixel, per frame and per stage: a hash of the pixel alone would
// repeat the same samples every frame, and accumulation would converge to a biased
// image.
void seedPixel(ivec2 px, uint stage) {
  uint pixelIndex = uint(px.y) * rtgi.width + uint(px.x);
  rngState =
      pcgHash(pcgHash(pcgHash(rtgi.seed + stage * 0x9e3779b9u) + pixelIndex) + rtgi.frameIndex);
}

// Where rays leave the surface: off it along the normal, past the voxels the surface
// touches (surfaceRayOffset).
vec3 rayOrigin(Surface s) { return s.p + s.n * (surfaceRayOffset(s.n) * octreeVoxelSize()); }

// Where rays leave the surface at px: rayOrigin, but off the surface's own normal
// where the G-buffer packed it (a mapped normal lying almost in the surface would
// start the ray inside the surface's voxels, which then shadow it).
vec3 surfaceRayOrigin(ivec2 px, Surface s) {
  float code = texelFetch(gEmission, px, 0).w;
  if (code == 0.0) return rayOrigin(s);
  Surface g = s;
  g.n = unpackSurfaceNormal(code);
  return rayOrigin(g);
}

// Interleaving (interleave_shared.h): with N > 1 a pixel traces new rays on every
// N-th frame only, in a 4x4 ordered order. Accumulation keeps a sample count per
// pixel, so the image converges to the same mean, N times slower per frame.
bool tracesEveryPixel() {
  return interleaveEveryPixel(rtgi.interleave, rtgi.frameIndex,
                              (rtgi.workFlags & kRtgiSparseStart) != 0u);
}

// The rank of this frame's turn: the pixels of rank r with (r + frame) % N == 0 trace.
uint turnRank() { return interleaveTurn(rtgi.interleave, rtgi.frameIndex); }

bool tracesThisFrame(ivec2 px) {
  return tracesEveryPixel() || interleaveTraces(px, rtgi.interleave, rtgi.frameIndex);
}

#ifdef RTGI_PIXEL_LIST
layout(std430, binding = kPixelListBinding) readonly buffer PixelList {
  PixelListHeader pixelHeader;
  uint pixels[];
};
#endif
#ifdef RTGI_TRACED_IMAGE
layout(binding = kTracedImage, r8ui) uniform readonly uimage2D tracedIn;
#endif

bool selectedByList() { return rtgi.selectKind != kSelectPattern && rtgi.frameIndex != 0u; }

bool outside(ivec2 px) {
  if (px.x >= int(rtgi.width) || px.y >= int(rtgi.height)) return true;
#ifdef RTGI_TRACED_IMAGE
  if (selectedByList()) return imageLoad(tracedIn, px).x == 0u;
#endif
  return !tracesThisFrame(px);
}

// The tracing stages run one invocation per pixel that traces this frame, packed:
// a SIMD vector of a software rasterizer then has all its lanes busy whatever the
// interleave (a mask over a full-image dispatch would leave most lanes idle).
// Pixels come block by block (4x4), so neighbouring lanes trace neighbouring pixels.
// False past the last pixel.
// RTGI_SPECULAR_LIST (the specular stage): the list at kPixelListBinding is
// rtgi_specular_select.comp's, of the specular pixels among those, whatever selects
// them.
bool tracePixel(out ivec2 px) {
  uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * kRtgiTraceGroup +
           gl_LocalInvocationID.x;
#ifdef RTGI_SPECULAR_LIST
  if (i >= pixelHeader.count.x) return false;
  uint code = pixels[i];
  px = ivec2(code & 0xffffu, code >> 16u);
  return true;
#endif
#ifdef RTGI_PIXEL_LIST
  if (selectedByList()) {
    if (i >= pixelHeader.count.x) return false;
    uint code = pixels[i];
    px = ivec2(code & 0xffffu, code >> 16u);
    return true;
  }
#endif
  return interleavePixel(i, rtgi.width, rtgi.height, rtgi.interleave, rtgi.frameIndex,
                         tracesEveryPixel(), px);
}

#endif  // VOXGI_RTGI_COMMON_GLSL
