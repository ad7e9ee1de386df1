// rtgi and dvr data shared by C++ (src/render/rtgi_pass.*, dvr_pass.*) and GLSL.
#ifndef VOXGI_RTGI_SHARED_H
#define VOXGI_RTGI_SHARED_H

#include "gpu_types.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

VOXGI_CONST uint kRtgiParamsBinding = 3u;  // uniform block
// G-buffer, read as textures (texelFetch).
VOXGI_CONST uint kGPositionUnit = 4u;  // rgba32f: world position, w 1 where covered
VOXGI_CONST uint kGNormalUnit = 5u;    // rgba16f: shading normal (towards the viewer), w roughness
VOXGI_CONST uint kGAlbedoUnit = 6u;    // rgba8: base colour, w metallic
VOXGI_CONST uint kGEmissionUnit = 7u;  // rgba16f: emitted radiance
// Images written by the per-pixel stages and read by accumulate.
VOXGI_CONST uint kDirectImage = 0u;
VOXGI_CONST uint kIndirectImage = 1u;
VOXGI_CONST uint kSpecularImage = 2u;
VOXGI_CONST uint kAccumImage = 3u;  // the running mean (the renderer's HDR target)
VOXGI_CONST int kMaxExactEmitters = 8;
VOXGI_CONST uint kMaxInterleave =
    16u;  // a 4x4 ordered pattern  // RtgiPass::Settings::exactEmitters at most
VOXGI_CONST uint kRtgiTraceGroup = 64u;  // tracing stages: 1D groups over packed pixels
VOXGI_CONST uint kRtgiGroupX = 8u;
VOXGI_CONST uint kRtgiGroupY = 8u;

// Which terms accumulate adds.
VOXGI_CONST uint kRtgiHasDirect = 1u;
VOXGI_CONST uint kRtgiHasIndirect = 2u;
VOXGI_CONST uint kRtgiHasSpecular = 4u;

// Below this roughness a surface is a mirror: one reflected ray, and direct light
// adds no highlight of its own (the ray sees the lights' voxels).
VOXGI_CONST float kMirrorRoughness = 0.05f;
// Dielectrics rougher than this reflect too little, too blurred, to trace.
VOXGI_CONST float kGlossyRoughness = 0.6f;

struct RtgiParams {
  uvec4 frame;         // x frame index since accumulation restarted, y seed, z width, w height
  uvec4 counts;        // x lights, y emitters, z flags (kRtgiHas*), w emitters sampled exactly (<=)
  vec4 camera;         // xyz position
  vec4 cameraRight;    // right * tan(fov/2) * aspect (dvr camera rays)
  vec4 cameraUp;       // up * tan(fov/2)
  vec4 cameraForward;  // w: opacity at which dvr stops
  uvec4 work;          // x: interleave N (1, 2, 4, 8, 16): a pixel traces every N-th frame
};

#ifdef __cplusplus
static_assert(sizeof(RtgiParams) == 112);
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_RTGI_SHARED_H
