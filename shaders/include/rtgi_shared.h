// rtgi and dvr data shared by C++ (src/render/rtgi_pass.*, dvr_pass.*) and GLSL.
#ifndef VOXGI_RTGI_SHARED_H
#define VOXGI_RTGI_SHARED_H

#include "bindings_shared.h"
#include "gpu_types.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

VOXGI_CONST uint kMaskBins = 256u;
// Denoiser (RtgiPass::Settings::denoise). Accumulate keeps, beside each pixel's mean,
// the running mean of its samples' luminance and squared luminance (rg32f), after
// the light is divided by the surface's base colour; reproject carries them over a
// camera move as it carries the mean.
// A uniform of the denoise passes (location): x the spacing of the taps in pixels,
// y 1 on the last pass.
VOXGI_CONST int kDenoisePassLocation = 0;
// The filter: this many passes of the a-trous wavelet, the i-th with taps 2^i
// pixels apart (a 3x3 kernel: together they reach 31 pixels either way).
VOXGI_CONST int kDenoisePasses = 5;
// Below this many samples a pixel's variance is estimated from its neighbours'.
VOXGI_CONST float kDenoiseTemporalSamples = 4.0f;
// How the pixels that trace are chosen (RtgiParams::selectKind).
VOXGI_CONST uint kSelectPattern = 0u;   // every interleave-th frame, Bayer order
VOXGI_CONST uint kSelectMask = 1u;      // the pattern, plus pixels whose mask exceeds selectLevel
VOXGI_CONST uint kSelectUniform = 2u;   // the pattern, plus a random selectLevel of the others
VOXGI_CONST int kMaxExactEmitters = 8;  // RtgiPass::Settings::exactEmitters at most
VOXGI_CONST uint kMaxInterleave = 16u;  // a 4x4 ordered pattern
// RtgiParams::workFlags.
// The first frame of an accumulation traces the pattern only, like the others, and
// a pixel that has not traced yet shows the light of traced neighbours on its surface
// (RtgiPass::Settings::sparseStart).
VOXGI_CONST uint kRtgiSparseStart = 1u;
VOXGI_CONST uint kRtgiTraceGroup = 64u;  // tracing stages: 1D groups over packed pixels
VOXGI_CONST uint kRtgiGroupX = 8u;
VOXGI_CONST uint kRtgiGroupY = 8u;
VOXGI_CONST uint kDenoisePrepareGroup = 16u;  // rtgi_denoise_prepare.comp: square groups
VOXGI_CONST uint kLightTileSize = 8u;  // rtgi_light_tiles.comp: a tile's width and height in pixels
VOXGI_CONST uint kLightTileSamples =
    kLightTileSize * kLightTileSize;  // emitters drawn per light tile, one per lane

// RtgiParams::flags: which terms accumulate adds.
VOXGI_CONST uint kRtgiHasDirect = 1u;
VOXGI_CONST uint kRtgiHasIndirect = 2u;
VOXGI_CONST uint kRtgiHasSpecular = 4u;
// The voxels hold every bounce (the default): the indirect stage's path may go on
// past a hit whose voxel cannot stand for its side (rtgi_indirect.comp).
VOXGI_CONST uint kRtgiAllBounces = 8u;
// This frame starts from the reproject stage's mean (kReprojectedImage).
VOXGI_CONST uint kRtgiReprojecting = 16u;
// The caustics stage ran: accumulate adds its light (kRtgiCausticBinding).
VOXGI_CONST uint kRtgiHasCaustics = 32u;
// The caustics stage aims its photons at the bounding spheres of at most this many
// runs of mirror triangles (RtgiPass::causticTargets; more are merged).
VOXGI_CONST int kMaxCausticTargets = 16;
// Vertices an indirect path visits on the triangles at most, the first hit included.
VOXGI_CONST int kMaxIndirectVertices = 3;

// Below this roughness a surface is a mirror: one reflected ray, and direct light
// adds no highlight of its own (the ray sees the lights' voxels).
VOXGI_CONST float kMirrorRoughness = 0.05f;
// With a BVH: mirrors a reflected ray passes on from before it is shaded.
VOXGI_CONST int kMaxMirrorChain = 4;

struct RtgiParams {
  // The frame: its index since accumulation restarted, the seed, the image's size.
  uint frameIndex;
  uint seed;
  uint width;
  uint height;
  // The scene's punctual lights and emitters, and the kRtgi* flags above.
  uint lightCount;
  uint emitterCount;
  uint flags;
  uint causticPhotons;  // the caustics stage's photons this frame
  vec4 camera;          // xyz position
  vec4 cameraRight;     // right * tan(fov/2) * aspect (dvr camera rays)
  vec4 cameraUp;        // up * tan(fov/2)
  vec4 cameraForward;   // xyz the view direction; w: opacity at which dvr stops
  // Which pixels trace: every interleave-th frame (1, 2, 4, 8, 16), and beyond that
  // pattern those selectKind (kSelect*) picks by selectLevel (the mask's threshold
  // or the uniform share, as float bits); workFlags: kRtgiSparseStart.
  uint interleave;
  uint selectLevel;
  uint selectKind;
  uint workFlags;
  // Reprojection: the previous frame's view-projection (without its jitter), and
  // the history a pixel keeps when the camera moved, in frames: at most historyCap,
  // glossyHistory on glossy surfaces, mirrorHistory on mirrors, edgeHistory on
  // edges between surfaces.
  vec4 previousViewProj[4];
  float historyCap;
  float glossyHistory;
  float mirrorHistory;
  float edgeHistory;
  // The denoiser's edge stops (RtgiPass::Settings::denoiseLuminance, denoisePlane).
  float denoiseLuminance;
  float denoisePlane;
  // The angle between neighbouring pixels' rays, in radians at the image's centre:
  // what a pixel spans at a distance of 1.
  float pixelSpread;
  uint causticTargets;  // the mirrors' bounding spheres the photons aim at
};

// The temporal upsampler (rtgi_upsample.comp, RenderSettings::renderScale < 1):
// rtgi renders at the internal size, its G-buffer offset each frame by a sub-pixel
// jitter, and each frame's fresh samples land in the output pixel that holds their
// jittered position.
struct UpsampleParams {
  uvec4 size;   // xy the output size
  vec4 jitter;  // xy this frame's jitter, in internal pixels (as the G-buffer's)
};

// Pixels that trace this frame, appended by rtgi_select.comp; `groups` doubles as
// the indirect dispatch of the tracing stages.
struct PixelListHeader {
  uvec4 groups;  // x: work groups of kRtgiTraceGroup, y 1, z 1
  uvec4 count;   // x: pixels listed
};

#ifndef __cplusplus
// Whether two pixels show the same surface, for the work mask's edges and the light a
// sparse start lends: both drawn or both not, normals within 25 degrees, distances
// from the camera within 5%.
bool sameSurface(bool covered0, vec3 n0, float d0, bool covered1, vec3 n1, float d1) {
  return covered0 == covered1 && dot(n0, n1) > 0.9 && abs(d1 - d0) < 0.05 * d0;
}
#endif

#ifdef __cplusplus
static_assert(sizeof(RtgiParams) == 208);
static_assert(sizeof(PixelListHeader) == 32);
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_RTGI_SHARED_H
