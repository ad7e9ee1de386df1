#version 450 core
// Voxelization, geometry stage: each triangle is projected orthographically along
// its dominant axis (voxel_triangle.glsl). With the compute path for small
// triangles (voxelize_small.comp) the raster draws only the triangles it passed on.
#include "scene_shared.h"
#include "voxel_shared.h"

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };

#include "voxel_triangle.glsl"

layout(location = 0) in vec3 vGrid[];
layout(location = 1) in vec3 vNormal[];
layout(location = 2) in vec2 vUv[];
#if defined(VOXGI_UV2) && !defined(VOXGI_NO_EMISSION)
layout(location = 4) in vec2 vUv2[];
layout(location = 6) centroid out vec2 gUv2;
#endif
#ifndef VOXGI_NO_COLORS
layout(location = 3) in vec4 vColor[];
layout(location = 5) centroid out vec4 gColor;
#endif

layout(location = 0) centroid out vec3 gNormal;
layout(location = 1) centroid out vec2 gUv;
layout(location = 2) flat out int gAxis;    // 0: x, 1: y, 2: z is the projection axis
layout(location = 3) flat out vec4 gPlane;  // swizzled plane: z = plane.x + plane.y*u + plane.z*v
layout(location = 4) flat out vec2 gDepth;  // the triangle's swizzled z range

void main() {
  vec3 n;
  int axis = voxelProjectionAxis(vGrid[0], vGrid[1], vGrid[2], n);
  if (axis < 0) return;  // degenerate in grid space
  vec3 s[3] = vec3[3](voxelSwizzle(vGrid[0], axis), voxelSwizzle(vGrid[1], axis),
                      voxelSwizzle(vGrid[2], axis));
  vec4 plane = voxelPlane(s[0], voxelSwizzle(n, axis));
  vec2 depth = voxelDepthRange(s[0], s[1], s[2]);
  float res = voxel.gridInfo.x;
  for (int i = 0; i < 3; ++i) {
    gNormal = vNormal[i];
    gUv = vUv[i];
#if defined(VOXGI_UV2) && !defined(VOXGI_NO_EMISSION)
    gUv2 = vUv2[i];
#endif
#ifndef VOXGI_NO_COLORS
    gColor = vColor[i];
#endif
    gAxis = axis;
    gPlane = plane;
    gDepth = depth;
    // grid [0, N] -> clip [-1, 1]; depth is not rasterized (no depth attachment)
    gl_Position = vec4(s[i].xy / res * 2.0 - 1.0, 0.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}
