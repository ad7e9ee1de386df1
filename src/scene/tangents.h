// Tangent frames for normal maps, generated when a glTF primitive has none.
//
// The glTF spec asks for MikkTSpace tangents where a normal-mapped primitive has no
// TANGENT, since that is what baking tools assume. This follows M. Mikkelsen,
// "Simulation of Wrinkled Surfaces Revisited" (Master's thesis, University of
// Copenhagen, 2008), ch. 4:
//   - each triangle's tangent is dP/du, solved from its edges and UV differences;
//     triangles whose UVs have no area give none;
//   - at each corner that tangent is projected into the plane of the corner's
//     vertex normal, normalized, and weighted by the corner's angle (measured in
//     that plane), so a vertex's result does not depend on how the surface around
//     it is split into triangles;
//   - corners are pooled over every triangle that shares the corner's position,
//     normal and UV exactly (so split vertices get one tangent), and, separately,
//     by the orientation of the triangle's UV map (a mirrored UV island keeps a
//     tangent of its own, with the opposite handedness);
//   - the pooled sum is orthogonalized against the normal once more (Gram-Schmidt)
//     and normalized; w = +1 when (normal, tangent, dP/dv) is right-handed, -1 if not
//     (glTF: bitangent = w * cross(normal, tangent)).
// A vertex index shared by triangles of both orientations takes the orientation of
// the larger angle sum (a vertex cannot hold two tangents); a corner with no usable
// triangle around it gets any unit vector perpendicular to its normal.
// Tests: tests/scene/tangents_test.cpp (against the TANGENT of a quad, mirrored
// UVs, invariance to splitting).
#ifndef VOXGI_SCENE_TANGENTS_H
#define VOXGI_SCENE_TANGENTS_H

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace voxgi::scene {

// Tangents (xyz unit, w +-1) for every vertex; `indices` lists triangles (three
// indices into the attribute arrays, which have equal sizes; normals unit length).
std::vector<glm::vec4> generateTangents(const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::vec3>& normals,
                                        const std::vector<glm::vec2>& uvs,
                                        const std::vector<uint32_t>& indices);

// A unit vector perpendicular to unit n (the fallback tangent).
glm::vec3 anyPerpendicular(const glm::vec3& n);

}  // namespace voxgi::scene

#endif  // VOXGI_SCENE_TANGENTS_H
