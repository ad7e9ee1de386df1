// Every binding point, texture unit and image unit that C++ and GLSL share, in one
// place, grouped by kind and by the pass that binds it.
//
// OpenGL keeps a separate table per kind: uniform-block bindings, SSBO bindings,
// texture units and image units. A number means something only within its kind.
//
// The rule for sharing a number within one kind: two names may share it only when
// no program reads both. Each pass binds its own set right before its dispatch or
// draw (the scene's buffers and textures included), so what an earlier pass left
// on a number is replaced before a program that reads that number runs. A program
// reads the names its shader sources (with their includes) mention; the test
// tests/render/bindings_test.cpp checks this for every shader under shaders/, that
// image units stay below kMinImageUnits, and the SSBO needs stated below.
//
// A pass that reads another layer's data (rtgi and dvr read the octree; the
// octree reads the voxel list; every scene pass reads the scene's buffers) uses
// that layer's numbers, so a pass's own numbers start past them.
#ifndef VOXGI_BINDINGS_SHARED_H
#define VOXGI_BINDINGS_SHARED_H

#include "gpu_types.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// GL 4.5's minimum of GL_MAX_IMAGE_UNITS: image units 0 to 7 exist on every driver.
VOXGI_CONST uint kMinImageUnits = 8u;

// What the shaders ask of SSBOs, beyond GL 4.5's minimum of 8 for each: the highest
// SSBO binding + 1 (GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS), and the most SSBOs one
// compute program (GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS) or one program with a
// fragment shader (GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS) reads. The context
// refuses a driver that offers less (gl/context.cpp); the bindings test keeps these
// equal to what the shaders use.
VOXGI_CONST uint kRequiredSsboBindings = 27u;
VOXGI_CONST uint kRequiredComputeSsboBlocks = 15u;
VOXGI_CONST uint kRequiredFragmentSsboBlocks = 9u;

// ---------------------------------------------------------------------------
// Uniform blocks. One number per block: a program may read several.
VOXGI_CONST uint kFrameBinding = 0u;           // scene passes: GpuFrame
VOXGI_CONST uint kVoxelParamsBinding = 1u;     // voxelize, resolve, voxel points: VoxelParams
VOXGI_CONST uint kPtParamsBinding = 1u;        // path tracer: GpuPtParams (never with voxels)
VOXGI_CONST uint kOctreeParamsBinding = 2u;    // octree passes, rtgi, dvr: OctreeParams
VOXGI_CONST uint kRtgiParamsBinding = 3u;      // rtgi, dvr: RtgiParams
VOXGI_CONST uint kUpsampleParamsBinding = 4u;  // rtgi's temporal upsampler: UpsampleParams

// ---------------------------------------------------------------------------
// SSBOs.

// The scene (scene_shared.h), for every pass that shades it.
VOXGI_CONST uint kMaterialBinding = 0u;
VOXGI_CONST uint kLightBinding = 1u;
VOXGI_CONST uint kEmitterBinding = 2u;
VOXGI_CONST uint kLightTreeBinding = 23u;  // GpuLightNode[] (light_tree_shared.h): rtgi's shadows
// Every pass that replaces a non-finite value rather than let it poison what it
// writes (nonfinite.glsl): one uint, the count of values replaced. Tests require it
// to stay 0; `--stats` reports it as nonfinite_terms.
VOXGI_CONST uint kNonfiniteCountBinding = 24u;

// Voxelization (voxel_shared.h). The sparse sums: a brick map holds, per brick,
// the epoch and the brick's slot in a pool; the pool holds, per voxel, the epoch
// and the voxel's slot; the sums live per voxel slot in three SSBOs of one uvec4
// per slot. The resolved grid is the list of occupied voxels and, at the same
// index, their attributes; the octree passes and the voxel points read those two.
VOXGI_CONST uint kVoxelStatsBinding = 3u;  // VoxelStats
VOXGI_CONST uint kVoxelListBinding = 4u;   // packed coordinates of occupied voxels
VOXGI_CONST uint kBrickMapBinding = 5u;    // epoch | brick slot, per brick
VOXGI_CONST uint kSlotSumsABinding = 6u;   // uvec4 per voxel slot
VOXGI_CONST uint kSlotSumsNBinding = 7u;
VOXGI_CONST uint kSlotSumsEBinding = 8u;
VOXGI_CONST uint kBrickPoolBinding = 9u;     // epoch | voxel slot, 64 per brick slot
VOXGI_CONST uint kVoxelAttribBinding = 17u;  // uvec4 attributes per listed voxel
// The compute path for small triangles (voxelize_small.comp) passes the others on
// to the raster: their indices, and the indirect commands (5 uints) per group.
VOXGI_CONST uint kLargeIndexBinding = 10u;
VOXGI_CONST uint kDrawCommandBinding = 11u;
// Fragments whose voxel another thread was still claiming when the wait ran out
// (VoxelDeferred records, added after the raster by voxelize_deferred.comp).
VOXGI_CONST uint kVoxelDeferredBinding = 12u;

// The octree (octree_shared.h): the voxelization's sum buffers are done with by
// the time it builds, so it takes their numbers; it reads the voxel list (4) and
// attributes (17).
VOXGI_CONST uint kOctreeNodeBinding = 5u;
VOXGI_CONST uint kOctreeRadianceBinding = 6u;
VOXGI_CONST uint kOctreeMaterialBinding = 7u;
VOXGI_CONST uint kOctreeEmissionBinding = 8u;
VOXGI_CONST uint kOctreeCounterBinding = 9u;
// uint per light slot, octree_bounce.comp (OCTREE_BVH): the triangle an oriented
// leaf's side lies on, plus 1 (0: not looked for yet; kOctreeNoSurface: none). The
// build's counters are done with by then: it takes their number.
VOXGI_CONST uint kOctreeSurfaceBinding = 9u;
VOXGI_CONST uint kOctreeNoSurface = 0xFFFFFFFFu;
VOXGI_CONST uint kOctreeScratchBinding = 10u;  // radiance of the previous bounce; the estimate
                                               // the average pass blends in
VOXGI_CONST uint kOctreeLightCdfBinding = 11u;
VOXGI_CONST uint kOctreeDirectBinding = 12u;  // direct light of each leaf, while bouncing
VOXGI_CONST uint kOctreeRayBinding = 13u;     // octree_raycast.comp: OctreeRay[] in
VOXGI_CONST uint kOctreeRayHitBinding = 14u;  // octree_raycast.comp: ivec4[] out
// uvec2 per bounce ray of the first estimate's chain (octree_bounce.comp): the light
// slot it brought the light of and the factor it took it with. Only the bounce
// pass binds it, so it takes octree_raycast's number.
VOXGI_CONST uint kOctreeReplayBinding = 13u;
VOXGI_CONST uint kOctreeMeanBinding = 18u;  // vec4 per node: the running mean of the radiance
// vec4 per node: the running mean of the radiance less its direct light (the voxel
// bounces alone), which rtgi reads behind a hit it lights exactly.
VOXGI_CONST uint kOctreeBounceBinding = 25u;

// rtgi (rtgi_shared.h), which reads the scene and the octree beside its own.
VOXGI_CONST uint kPixelListBinding = 15u;      // PixelList
VOXGI_CONST uint kMaskHistogramBinding = 16u;  // uint[kMaskBins]
// The specular pixels among those that trace (rtgi_specular_select.comp writes it;
// the specular stage reads it at kPixelListBinding): a PixelList. Only the
// selection binds it, so it takes the mask histogram's number.
VOXGI_CONST uint kSpecularListBinding = 16u;
// The shadows stage's light reservoirs (ReSTIR DI, rtgi_restir.glsl): vec4 per
// pixel. With few enough emitters that the light tree draws among them all, where
// reservoirs are not reused, the same binding holds the light tiles
// (rtgi_light_tiles.comp): the emitters drawn for each tile of pixels.
VOXGI_CONST uint kRtgiReservoirBinding = 26u;
// The caustics stage (rtgi_caustics.comp): its light per pixel (3 floats, written by
// atomic additions, read by accumulate), and the mirrors' bounding spheres its
// photons aim at (vec4). No octree_raycast or bounce pass runs beside them, so they
// take those passes' numbers.
VOXGI_CONST uint kRtgiCausticBinding = 13u;
VOXGI_CONST uint kRtgiCausticTargetBinding = 14u;
// The BVH's stages (RTGI_BVH; render/gpu_bvh.h): the scene's index buffer (uint
// per triangle corner), which a triangle's record points into (GpuPtTriangle).
VOXGI_CONST uint kRtgiBvhIndexBinding = 19u;
// The table of textures (uvec4 each, see kPtTextureBinding).
VOXGI_CONST uint kRtgiBvhTextureBinding = 20u;
// Vertex colours at the hit (RTGI_BVH_COLORS: the scene has them, the plan reads
// them): the scene's colour buffer (see kPtColorBinding).
VOXGI_CONST uint kRtgiBvhColorBinding = 21u;
// Tangents at the hit (RTGI_BVH_TANGENTS: the scene has normal maps, the plan reads
// them): the scene's tangent buffer (see kPtTangentBinding).
VOXGI_CONST uint kRtgiBvhTangentBinding = 22u;

// The path tracer (pathtrace_shared.h), which reads the scene's materials and
// lights and nothing of the voxels or the octree.
// The scene's index buffer (uint per triangle corner), which a triangle's record
// points into (GpuPtTriangle).
VOXGI_CONST uint kPtIndexBinding = 5u;
VOXGI_CONST uint kPtEmissiveBinding = 6u;
VOXGI_CONST uint kPtCounterBinding = 7u;  // uint: paths cut short by the loop budget
// Textures (unless VOXGI_NO_TEXTURES): uvec4 per texture of the scene, x first
// texel in kPtTexelTexUnit, y width, z height, w 1 if sRGB-encoded (colour).
VOXGI_CONST uint kPtTextureBinding = 8u;
// Vertex colours (VOXGI_BVH_COLORS): the scene's colour buffer, vec4 per vertex
// (COLOR_0, RGBA).
VOXGI_CONST uint kPtColorBinding = 9u;
// Tangents for normal maps (VOXGI_BVH_TANGENTS): the scene's tangent buffer, vec4 per
// vertex (xyz, w handedness).
VOXGI_CONST uint kPtTangentBinding = 10u;

// ---------------------------------------------------------------------------
// Texture units.

// The scene's material textures, for the passes that draw it. The base colour is
// unit 0; the others sit past every unit those passes bind for their own use.
VOXGI_CONST uint kBaseColorUnit = 0u;
VOXGI_CONST uint kEmissiveUnit = 9u;
VOXGI_CONST uint kMetallicRoughnessUnit = 10u;
VOXGI_CONST uint kNormalUnit = 11u;     // normalTexture (linear)
VOXGI_CONST uint kOcclusionUnit = 12u;  // occlusionTexture (linear; the raster baseline only)
VOXGI_CONST uint kHdrInputUnit = 0u;    // tonemap input

// Voxelization's compute path: the scene's geometry as buffer textures.
VOXGI_CONST uint kVoxelVertexUnit = 1u;  // samplerBuffer: the scene's vertices
VOXGI_CONST uint kVoxelIndexUnit = 2u;   // usamplerBuffer: the scene's indices
VOXGI_CONST uint kVoxelColorUnit = 3u;   // samplerBuffer: the vertex colours (RGBA)

// The octree, for the passes that trace it (octree.glsl): the node words as r32ui.
VOXGI_CONST uint kOctreeNodeTexUnit = 8u;

// The path tracer: the BVH nodes and the triangles, read as RGBA32UI buffer
// textures (a struct is sizeof / 16 texels; floats as their bit patterns). On
// llvmpipe a texelFetch from a buffer texture costs much less than the same load
// from an SSBO.
VOXGI_CONST uint kPtNodeTexUnit = 0u;
VOXGI_CONST uint kPtTriangleTexUnit = 1u;
// The scene's vertex buffer (scene::Vertex: position, normal, uv, uv2), read as five
// RG32F texels a vertex through the index buffer at a hit.
VOXGI_CONST uint kPtVertexTexUnit = 2u;
// Every texture's RGBA8 texels, one R32UI texel each, rows top first.
VOXGI_CONST uint kPtTexelTexUnit = 3u;

// rtgi. The BVH's nodes and triangles as buffer textures, the scene's vertices at
// the hit, and the textures (a textured BVH, unless VOXGI_NO_TEXTURES), as the path
// tracer reads them (kPtVertexTexUnit, kPtTexelTexUnit).
VOXGI_CONST uint kRtgiBvhNodeUnit = 0u;
VOXGI_CONST uint kRtgiBvhTriangleUnit = 1u;
VOXGI_CONST uint kRtgiBvhVertexUnit = 2u;
VOXGI_CONST uint kRtgiBvhTexelUnit = 3u;
// The G-buffer, read with texelFetch.
VOXGI_CONST uint kGPositionUnit = 4u;  // rgba32f: world position, w 1 + material where covered
VOXGI_CONST uint kGNormalUnit = 5u;    // rgba16f: shading normal (towards the viewer), w roughness
VOXGI_CONST uint kGAlbedoUnit = 6u;    // rgba8: base colour, w metallic
// rgba16f: emitted radiance; w the surface's own normal in scenes with normal maps
// (packSurfaceNormal of normal_map_shared.h), else 0.
VOXGI_CONST uint kGEmissionUnit = 7u;
// Reprojection (a frame after the camera moved): the running mean as it was before
// this frame (the accumulation target, read as a texture), and the previous
// frame's G-buffer position and normal.
VOXGI_CONST uint kHistoryUnit = 9u;
VOXGI_CONST uint kGPreviousPositionUnit = 10u;
VOXGI_CONST uint kGPreviousNormalUnit = 11u;
// rgba16f: the surface point's world position last frame less this frame's (moving
// meshes; 0 elsewhere).
VOXGI_CONST uint kGMotionUnit = 12u;
VOXGI_CONST uint kHistoryMomentsUnit = 13u;  // the denoiser's moments before this frame
// The denoiser's running mean of the direct term before this frame (reproject,
// prepare), and what reproject made of it and of the moments, which accumulate reads
// on a frame after a move (textures: accumulate's image units are all taken).
VOXGI_CONST uint kHistoryDirectUnit = 14u;
VOXGI_CONST uint kReprojectedMomentsUnit = 14u;
VOXGI_CONST uint kReprojectedDirectUnit = 15u;
// rtgi's upsampled output (a render scale below 1), shown by the tonemap pass: the
// output's history (rgba32f at the output size: per pixel the sum of the samples
// that landed in it, and their count) and rtgi's image as shown at the internal
// size (read with a bilinear filter).
VOXGI_CONST uint kUpsampleHistoryUnit = 9u;
VOXGI_CONST uint kUpsampleShownUnit = 10u;

// ---------------------------------------------------------------------------
// Image units.

// rtgi's G-buffer made by rays (rtgi_gbuffer.comp), the five images gbuffer.frag
// draws to, before any other stage of the frame binds its images.
VOXGI_CONST uint kGbufferPositionImage = 0u;  // rgba32f
VOXGI_CONST uint kGbufferNormalImage = 1u;    // rgba16f
VOXGI_CONST uint kGbufferAlbedoImage = 2u;    // rgba8
VOXGI_CONST uint kGbufferEmissionImage = 3u;  // rgba16f
VOXGI_CONST uint kGbufferMotionImage = 4u;    // rgba16f
// rtgi: the images written by the per-pixel stages and read by accumulate.
VOXGI_CONST uint kDirectImage = 0u;
VOXGI_CONST uint kIndirectImage = 1u;
VOXGI_CONST uint kSpecularImage = 2u;
VOXGI_CONST uint kAccumImage = 3u;  // the running mean (the renderer's HDR target)
// Work mask (frame budget): edges of the noisy image, the blurred mask, and which
// pixels trace this frame.
VOXGI_CONST uint kEdgeImage = 4u;     // r16f
VOXGI_CONST uint kMaskImage = 5u;     // r16f, in [0, 1)
VOXGI_CONST uint kTracedImage = 6u;   // r8ui: 1 where the pixel traces this frame
VOXGI_CONST uint kMaskKeyImage = 7u;  // rgba32ui: what the edges compare, per pixel
// Reprojection: the reprojected mean (rgba32f) that accumulate then reads in place
// of the target. It uses the mask key's unit, which accumulate and reproject do not
// read (accumulate reads units 0 to 6 beside it); each binds it before its dispatch,
// after the mask has run. The indirect stage reads its count of samples too.
VOXGI_CONST uint kReprojectedImage = 7u;
// Denoiser (rtgi_denoise.glsl), which filters two terms apart: the light straight
// from the lights (the direct stage's) and the light by way of other surfaces
// (indirect and specular). The running moments of each term's luminance (rgba32f:
// direct's mean and mean square, then the other's) and the running mean of the
// direct term (rgba32f) beside the accumulation target's mean of all; they use the
// mask's image units, which accumulate does not otherwise read. Reproject writes
// its moments and direct mean on the units of the mean's (accumulate reads them as
// textures, kReprojectedMomentsUnit and kReprojectedDirectUnit).
VOXGI_CONST uint kMomentsImage = 4u;
VOXGI_CONST uint kDirectMeanImage = 5u;
VOXGI_CONST uint kReprojectedMomentsImage = 4u;
VOXGI_CONST uint kReprojectedDirectImage = 5u;
// The denoise stage's own images: both terms of a pixel in one rgba32ui texel
// (rtgi_denoise.glsl, packDenoiseTerms), ping-ponged between the filter's passes;
// the last pass writes the denoised image (rgba32f).
VOXGI_CONST uint kDenoiseInImage = 0u;
VOXGI_CONST uint kDenoiseOutImage = 1u;
VOXGI_CONST uint kDenoiseKeyImage = 2u;  // rgba32ui: what the edge stops compare
VOXGI_CONST uint kDenoisedImage = 3u;
// The temporal upsampler's output history (rgba32f, the output size: per pixel the
// sum of the samples that landed in it and their count), on a unit the rtgi
// stages' images leave free (it reads the direct, indirect and specular images and
// the traced pixels beside it).
VOXGI_CONST uint kUpsampleHistoryImage = 3u;

// The path tracer: the running sum, its Kahan compensation, and the resolved mean.
VOXGI_CONST uint kPtSumImage = 0u;
VOXGI_CONST uint kPtCompensationImage = 1u;
VOXGI_CONST uint kPtOutputImage = 2u;

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_BINDINGS_SHARED_H
