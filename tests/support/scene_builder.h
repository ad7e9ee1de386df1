// Scenes made in code for tests, and transformed copies of glTF files.
#ifndef VOXGI_TESTS_SCENE_BUILDER_H
#define VOXGI_TESTS_SCENE_BUILDER_H

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxgi::test {

class SceneBuilder {
 public:
  int addMaterial(glm::vec3 albedo, glm::vec3 emission = glm::vec3(0.0f), bool doubleSided = true);
  // Triangles from consecutive position triples, one draw, flat normals.
  void addTriangles(const std::vector<glm::vec3>& corners, int material,
                    const glm::mat4& transform = glm::mat4(1.0f));
  // A closed box [lo, hi] (12 triangles, outward normals) under `transform`.
  void addBox(glm::vec3 lo, glm::vec3 hi, int material,
              const glm::mat4& transform = glm::mat4(1.0f));
  // A UV sphere: `rings` rings of 2 x `rings` quads, two flat triangles each, wound
  // to face its centre.
  void addSphere(glm::vec3 centre, float radius, int rings, int material,
                 const glm::mat4& transform = glm::mat4(1.0f));
  // Bounds, auto-scale and a framing camera, as the loader does.
  scene::Scene finish();
  scene::Scene& scene() { return scene_; }

 private:
  scene::Scene scene_;
};

// A white square (albedo 0.8, 1 m, facing +z) 0.5 m in front of a black wall (6 m),
// lit head-on by a directional light of 3 lux, seen from 3 m: the square's radiance
// is the same every frame (direct light only: the black wall sends nothing back) and
// everything else is exactly 0, so any light the square leaves behind after a move
// is a ghost.
scene::Scene squareBeforeWall();

// Lights s head-on by a directional light of 3 lux shining down -z and puts its
// camera at (0, 0, distance), looking down -z (near 0.1, far 10).
void lightHeadOnFromZ(scene::Scene* s, float distance);

// Adds the quad p[0..3] (counter-clockwise seen from its front) to s as one draw of
// two triangles, with its flat normal and the given corner UVs.
void addQuad(scene::Scene* s, int material, const glm::vec3 (&p)[4],
             const glm::vec2 (&uv)[4] = {{0, 0}, {0, 0}, {0, 0}, {0, 0}});

// Writes a copy of a .gltf (buffers embedded as data: URIs) whose scene sits under
// a new root node with the given translation and uniform scale; returns its path
// in a scratch directory. Cameras and lights move with the scene; point and spot
// intensities (candela: irradiance falls off as 1/distance^2) are multiplied by
// scale^2, so that the copy renders the same image. Directional lights (lux) and
// emissive surfaces (radiance) need no change.
std::string writeTransformedGltf(const std::string& source, glm::dvec3 translation, double scale);

// Writes a one-primitive .gltf (buffer embedded) into the scratch directory and
// returns its path: positions and triangle indices as given, normals as given (NaN
// and zero ones included) or none when empty, a grey double-sided material, a
// point light of `lightIntensity` candela at (0, 0, 2) and a camera at (0, 0, 3)
// looking down -z.
std::string writeMeshGltf(const std::string& name, const std::vector<glm::vec3>& positions,
                          const std::vector<uint32_t>& indices,
                          const std::vector<glm::vec3>& normals = {}, double lightIntensity = 10.0);

// Writes a .gltf (buffer embedded) whose node hierarchy is one chain `depth` levels
// deep: node i is node i + 1's only parent, each node translated by `step` (nothing
// when it is zero), and the deepest one draws the triangle (0, 0, 0), (1, 0, 0),
// (0, 1, 0). The triangle's world corners are its own plus depth x step. With
// `animated`, a LINEAR channel moves the root from `step` at t = 0 to step + (1, 0, 0)
// at t = 1. Returns its path in the scratch directory.
std::string writeDeepChainGltf(const std::string& name, int depth, glm::dvec3 step,
                               bool animated = false);

// A closed box of inner half-size 1: six slabs `thickness` thick that overlap at its
// edges (albedo 0.7), their inner faces on voxel boundaries of the 64^3 grid over
// [-2, 2]^3 it sets (voxels of 6.25 cm). Lit by a point light of 1 cd inside, at (0,
// 0.5, 0); with `outsideOn`, also by one of 1000 cd 0.3 beyond the +z wall. The
// leak tests' scene: nothing of the light outside may reach the inside.
scene::Scene sealedBox(float thickness, bool outsideOn);

}  // namespace voxgi::test

#endif  // VOXGI_TESTS_SCENE_BUILDER_H
