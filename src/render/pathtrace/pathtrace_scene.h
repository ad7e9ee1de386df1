// The scene as both path tracer devices see it, before any device-specific
// acceleration structure: every triangle in draw order with its material and
// corners, the emissive triangles as an alias table for next-event estimation,
// and the scene-scaled ray offset.
#ifndef VOXGI_RENDER_PATHTRACE_PATHTRACE_SCENE_H
#define VOXGI_RENDER_PATHTRACE_PATHTRACE_SCENE_H

#include <cstdint>
#include <vector>

#include "pathtrace_shared.h"
#include "render/bvh.h"
#include "scene/scene.h"

namespace voxgi::render {

struct PtScene {
  // Triangle t is the t-th index triple over the scene's draws (empty when built
  // without; buildPtScene).
  std::vector<BvhTriangle> triangles;
  std::vector<int> material;         // per triangle
  std::vector<uint32_t> firstIndex;  // per triangle: its first index in scene.indices
  // Emissive triangles chosen in proportion to power (area x luminance of the mean
  // radiance, twice for two-sided emitters) through a Walker alias table (Vose's construction);
  // each entry's w fields carry the table (see GpuPtEmissive).
  std::vector<gpu::GpuPtEmissive> emitters;
  // Per triangle: the area density with which next-event estimation picks a point
  // on it (probability / area), 0 for triangles that are not in the table. MIS
  // needs it when a BSDF-sampled ray hits an emitter.
  std::vector<float> emitterAreaPdf;
  // Ray offset along the geometric normal: 1e-5 of the scene's diagonal.
  float epsilon = 1e-5f;
};

// `textured`: the device reads textures (ptReadsTextures). Then an emissive
// triangle's chance follows its emissive texture's mean over it (Draw::emissiveMean;
// black ones are not in the table) and its entry names the texture; otherwise the
// material's emission alone.
// `keepTriangles` false: `triangles` stays empty (sceneTriangle reads them from the
// scene through firstIndex; GpuBvh builds from them so).
PtScene buildPtScene(const scene::Scene& scene, bool textured = true, bool keepTriangles = true);

// The positions of the triangle whose first index in scene.indices is `firstIndex`.
BvhTriangle sceneTriangle(const scene::Scene& scene, uint32_t firstIndex);

// Whether the path tracer reads textures: `allowed` (the effect plan) and some
// draw's material has one (base colour, emissive or metallic-roughness).
bool ptReadsTextures(const scene::Scene& scene, bool allowed);

// Whether the path tracer applies alpha masks: `allowed` (the effect plan) and some
// draw's material is alpha-masked or blended (glTF MASK or BLEND; texture_shared.h's
// alphaStops).
bool ptReadsAlphaMasks(const scene::Scene& scene, bool allowed);

// Every texture's RGBA8 texels, one uint each, rows top first, in one array;
// table[i] = (first texel of texture i, width, height, its flags: sRGB, wrap modes,
// nearest magnification; scene::Texture::tableFlags).
void buildPtTextures(const scene::Scene& scene, std::vector<glm::uvec4>* table,
                     std::vector<uint32_t>* texels);

// Vose's alias method over `weights` (not all zero): prob[i] is the chance of
// keeping i, alias[i] the other choice.
void buildAliasTable(const std::vector<double>& weights, std::vector<float>* prob,
                     std::vector<uint32_t>* alias);

}  // namespace voxgi::render

#endif  // VOXGI_RENDER_PATHTRACE_PATHTRACE_SCENE_H
