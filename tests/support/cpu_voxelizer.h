// A CPU reference voxelizer for tests: a voxel is set when a triangle overlaps
// its box, decided by the separating axis theorem over the 13 candidate axes
// (Akenine-Moller, "Fast 3D Triangle-Box Overlap Testing", 2001). Slow and exact.
#ifndef VOXGI_TESTS_CPU_VOXELIZER_H
#define VOXGI_TESTS_CPU_VOXELIZER_H

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace voxgi::test {

// Closed boxes: true if the triangle intersects [lo, hi].
bool triangleOverlapsBox(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                         const glm::dvec3& lo, const glm::dvec3& hi);

// N^3 occupancy (x fastest) of the scene's triangles over the grid of scene.scale.
std::vector<uint8_t> cpuVoxelize(const scene::Scene& scene, int resolution);

// Occupancy from a resolved albedo grid (RGBA8, opacity in alpha).
std::vector<uint8_t> occupancyFromAlbedo(const std::vector<uint8_t>& rgba);

// 6-connected flood fill of empty voxels from the grid's border: true if it reaches
// `inside` (a ray could pass from outside to that voxel).
bool reachableFromOutside(const std::vector<uint8_t>& occupied, int resolution, glm::ivec3 inside);

}  // namespace voxgi::test

#endif  // VOXGI_TESTS_CPU_VOXELIZER_H
