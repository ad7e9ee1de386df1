#version 450 core
// Voxelization, vertex stage: scene space -> grid space (voxel units, [0, N]).
#include "scene_shared.h"
#include "voxel_shared.h"

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };

#include "voxel_triangle.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec3 vGrid;
layout(location = 1) out vec3 vNormal;
layout(location = 2) out vec2 vUv;

void main() {
  vGrid = voxelGridPosition(inPosition);
  vNormal = inNormal;
  vUv = inUv;
}
