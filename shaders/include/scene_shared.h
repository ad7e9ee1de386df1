// Scene data as the GPU reads it (std430 SSBOs), shared by C++ and GLSL.
// C++ sees glm types; GLSL its own. Every struct is built from vec4 / 32-bit
// scalars and padded by hand; sizes and offsets are asserted in C++ and checked
// against the linked program in tests/render/scene_layout_gltest.cpp.
#ifndef VOXGI_SCENE_SHARED_H
#define VOXGI_SCENE_SHARED_H

#include "bindings_shared.h"
#include "gpu_types.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// Uniform locations.
VOXGI_CONST int kMaterialIndexLocation = 0;
VOXGI_CONST int kExposureLocation = 1;
VOXGI_CONST int kTonemapLocation = 2;
// The mask view: the mask's size over the image's (an rtgi render scale below 1 makes
// the mask smaller than the image it is shown in).
VOXGI_CONST int kTonemapInputScaleLocation = 3;
// rtgi's upsampled output: the internal image's weight (tonemap.frag, TONEMAP_UPSAMPLED).
VOXGI_CONST int kUpsampleWeightLocation = 4;
VOXGI_CONST int kAmbientLocation = 3;  // raster.frag: the uniform ambient radiance

// Vertex attribute locations (scene::GpuScene's vertex array): position, normal
// and uv (0, 1, 2) and uv2 (kUv2Attribute) from scene::Vertex; the vertex colour (COLOR_0, RGBA)
// from its own stream, present only in scenes that have one (otherwise a constant white).
VOXGI_CONST uint kColorAttribute = 3u;
// The position in the previous frame (motion vectors for rtgi's reprojection):
// scene::Vertex's, from a copy kept only while meshes move.
VOXGI_CONST uint kPreviousPositionAttribute = 4u;
// The tangent for normal maps (xyz, w handedness; scene::Scene::tangents), a stream
// of its own present only in scenes with normal maps.
VOXGI_CONST uint kTangentAttribute = 5u;
// Texture-coordinate channel 1 (scene::Vertex::uv2), read by the slots whose
// kMaterial*Uv2 bit is set.
VOXGI_CONST uint kUv2Attribute = 6u;
#if !defined(__cplusplus) && !defined(VOXGI_NO_TEXTURES) && !defined(VOXGI_NO_UV2)
// The raster stages pass channel 1 on: textures are read and a drawn material has a
// second channel (VOXGI_NO_UV2, scene::ShaderFeatures::secondUv, compiles it out).
#define VOXGI_UV2
#endif

// Material flags.
VOXGI_CONST uint kMaterialHasTexture = 1u;
VOXGI_CONST uint kMaterialDoubleSided = 2u;
VOXGI_CONST uint kMaterialAlphaMask = 4u;
VOXGI_CONST uint kMaterialHasEmissiveTexture = 8u;
VOXGI_CONST uint kMaterialHasMetallicRoughnessTexture = 16u;
VOXGI_CONST uint kMaterialHasNormalTexture = 32u;     // normalTexture, normalScale
VOXGI_CONST uint kMaterialHasOcclusionTexture = 64u;  // occlusionStrength, occlusionTexture
// The texture slots that read texture-coordinate channel 1 (scene::Vertex::uv2)
// rather than channel 0 (uv): one bit a slot. The base colour reads channel 0.
VOXGI_CONST uint kMaterialEmissiveUv2 = 128u;
VOXGI_CONST uint kMaterialMetallicRoughnessUv2 = 256u;
VOXGI_CONST uint kMaterialNormalUv2 = 512u;
VOXGI_CONST uint kMaterialOcclusionUv2 = 1024u;
VOXGI_CONST uint kMaterialAnyUv2 = 1920u;  // all four
// glTF alphaMode BLEND, drawn as coverage: a ray that meets the surface stops with
// probability alpha (texture_shared.h's alphaStops), so accumulated frames and samples
// blend it over what lies behind, and its shadows are as dense as it is opaque.
VOXGI_CONST uint kMaterialAlphaBlend = 2048u;

// The texture table's flags (the w of each entry; render/pathtrace/pathtrace_scene.h, read by
// texture_shared.h): sRGB-encoded texels, nearest magnification, and a 2-bit wrap
// mode per axis (scene::Texture::tableFlags).
VOXGI_CONST uint kTextureSrgb = 1u;
VOXGI_CONST uint kTextureNearest = 2u;  // glTF magFilter NEAREST: the texel under uv
VOXGI_CONST uint kTextureWrapSShift = 2u;
VOXGI_CONST uint kTextureWrapTShift = 4u;
VOXGI_CONST uint kTextureRepeat = 0u;
VOXGI_CONST uint kTextureClampToEdge = 1u;
VOXGI_CONST uint kTextureMirroredRepeat = 2u;

// Light types (KHR_lights_punctual).
VOXGI_CONST uint kLightDirectional = 0u;
VOXGI_CONST uint kLightPoint = 1u;
VOXGI_CONST uint kLightSpot = 2u;

// Emitter kinds (emissive surfaces as area lights).
VOXGI_CONST uint kEmitterTriangle = 0u;  // one triangle, integrated exactly
VOXGI_CONST uint kEmitterCluster = 1u;   // many small facets with one normal, as a disk

// Tonemap operators.
VOXGI_CONST int kTonemapClamp = 0;
VOXGI_CONST int kTonemapAces = 1;
VOXGI_CONST int kTonemapMask = 2;  // the rtgi work mask: red channel as grey, no exposure

struct GpuMaterial {
  vec4 baseColor;      // linear rgba
  vec3 emission;       // radiance
  uint normalTexture;  // with kMaterialHasNormalTexture
  float metallic;
  float roughness;
  float alphaCutoff;
  float normalScale;  // normalTexture.scale
  uint flags;
  uint texture;  // base-colour texture: index into Scene::textures (with kMaterialHasTexture)
  uint emissiveTexture;           // with kMaterialHasEmissiveTexture
  uint metallicRoughnessTexture;  // with kMaterialHasMetallicRoughnessTexture
  // With kMaterialHasOcclusionTexture, read by the raster baseline alone (the GI
  // modes compute their own occlusion).
  float occlusionStrength;
  uint occlusionTexture;
  float pad0;
  float pad1;
};

struct GpuLight {
  vec4 positionType;    // xyz world position, w type (kLight*)
  vec4 directionRange;  // xyz direction light travels, w range (0: infinite)
  vec4 radiance;        // rgb color x intensity (W/sr, or W/m^2 for directional)
  vec4 cone;            // x cos(inner), y cos(outer)
};

struct GpuEmitter {
  vec3 a;      // triangle: vertex 0 | cluster: centre
  uint kind;   // kEmitterTriangle or kEmitterCluster
  vec3 b;      // triangle: vertex 1 | cluster: unit normal
  float area;  // cluster: projected area (a triangle's comes from its vertices)
  vec3 c;      // triangle: vertex 2
  float pad0;
  vec3 radiance;
  uint twoSided;  // 1: it emits from both sides
};

struct GpuFrame {
  vec4 viewProj[4];  // column-major mat4, as columns
  vec4 cameraPosition;
  vec4 counts;  // x lights, y emitters
};

#ifdef __cplusplus
static_assert(sizeof(GpuMaterial) == 80);
static_assert(offsetof(GpuMaterial, normalTexture) == 28);
static_assert(offsetof(GpuMaterial, metallic) == 32);
static_assert(offsetof(GpuMaterial, occlusionStrength) == 64);
static_assert(offsetof(GpuMaterial, flags) == 48);
static_assert(offsetof(GpuMaterial, metallicRoughnessTexture) == 60);
static_assert(sizeof(GpuLight) == 64);
static_assert(sizeof(GpuEmitter) == 64);
static_assert(offsetof(GpuEmitter, kind) == 12);
static_assert(offsetof(GpuEmitter, area) == 28);
static_assert(offsetof(GpuEmitter, twoSided) == 60);
static_assert(sizeof(GpuFrame) == 96);
static_assert(offsetof(GpuFrame, cameraPosition) == 64);
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_SCENE_SHARED_H
