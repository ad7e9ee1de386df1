#version 450 core
// Voxelization, vertex stage: scene space -> grid space (voxel units, [0, N]).
#include "scene_shared.h"
#include "voxel_shared.h"

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };

#include "voxel_triangle.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
#if defined(VOXGI_UV2) && !defined(VOXGI_NO_EMISSION)
// Texture-coordinate channel 1: the emissive texture's where its kMaterialEmissiveUv2
// bit is set.
layout(location = kUv2Attribute) in vec2 inUv2;
#endif
#ifndef VOXGI_NO_COLORS
layout(location = kColorAttribute) in vec4 inColor;
#endif

layout(location = 0) out vec3 vGrid;
layout(location = 1) out vec3 vNormal;
layout(location = 2) out vec2 vUv;
#if defined(VOXGI_UV2) && !defined(VOXGI_NO_EMISSION)
layout(location = 4) out vec2 vUv2;
#endif
#ifndef VOXGI_NO_COLORS
layout(location = 3) out vec4 vColor;
#endif

void main() {
  vGrid = voxelGridPosition(inPosition);
  vNormal = inNormal;
  vUv = inUv;
#if defined(VOXGI_UV2) && !defined(VOXGI_NO_EMISSION)
  vUv2 = inUv2;
#endif
#ifndef VOXGI_NO_COLORS
  // Passed on as the offset from white: where every corner is white (a scene without
  // colours reads the constant white) the interpolated zeros stay exact, and so
  // does the base colour.
  vColor = inColor - 1.0;
#endif
}
