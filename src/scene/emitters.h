// Emissive surfaces as area lights for direct lighting without shadows.
//
// Small emitters (a few triangles, like a ceiling panel) are kept as triangles and
// integrated exactly over the receiver's hemisphere (Lambert's polygon formula,
// clipped to the horizon). Finely tessellated emitters (a UV-sphere lamp of 16k
// triangles) are grouped into clusters of facets with similar normals and
// positions; a cluster acts as a disk of the same projected area, whose on-axis
// irradiance L*A/(d^2 + A/pi) is exact, so nothing blows up near it.
#ifndef VOXGI_SCENE_EMITTERS_H
#define VOXGI_SCENE_EMITTERS_H

#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxgi::scene {

struct Emitter {
  enum class Kind { kTriangle, kCluster } kind = Kind::kTriangle;
  glm::vec3 v0{0.0f}, v1{0.0f}, v2{0.0f};  // triangle corners, or v0 = cluster center
  glm::vec3 normal{0.0f};                  // cluster: unit mean normal
  float area = 0.0f;                       // triangle area, or cluster projected area
  glm::vec3 radiance{0.0f};
  bool twoSided = false;
};

struct EmitterOptions {
  int exactTrianglesPerPrimitive = 32;  // primitives up to this size stay exact
  int maxEmitters = 4096;
};

// Triangles whose emissive texture is black over them are not lights: each
// triangle weighs by the texture's mean over it (Draw::emissiveMean).
std::vector<Emitter> buildEmitters(const Scene& scene, const EmitterOptions& options = {});

// Per draw: whether buildEmitters keeps its emitting triangles as triangles (true) or
// merges them into clusters (false; and false for a draw that does not emit). rtgi's
// highlights of triangle emitters are shared with its reflected rays, which must know
// a cluster's facets, which it lights as a disk, from them (GpuBvh).
std::vector<bool> exactEmitterDraws(const Scene& scene, const EmitterOptions& options = {});

// Fills Draw::emissiveMean for every draw whose material has an emissive texture:
// the texture's mean (linear) over each triangle: the mean of the texels whose
// centres lie in the triangle, or, for a triangle holding fewer than four, of the
// bilinear texture (as the path tracer reads it) at a stratified grid of points.
// Done once at load; the loader calls it.
void measureEmissiveTextures(Scene* scene);

// The radiance triangle t of draw d emits on average: the material's emission times
// its emissive texture's mean over the triangle.
glm::vec3 triangleEmission(const Scene& scene, const Draw& d, size_t t);

// Irradiance (per unit radiance, i.e. the geometric factor) at point p with normal
// n from one emitter: the shaders' own code (emitter_shared.h). Used by tests.
float emitterIrradianceFactor(const Emitter& e, const glm::vec3& p, const glm::vec3& n);

}  // namespace voxgi::scene

#endif  // VOXGI_SCENE_EMITTERS_H
