#version 450 core
// Voxelization, geometry stage: each triangle is projected orthographically along
// the axis its normal is most aligned with (Crassin & Green, "Octree-Based Sparse
// Voxelization Using the GPU Hardware Rasterizer", OpenGL Insights ch. 22), which
// maximises its rasterized area. Grid space is swizzled so that axis becomes z.
#include "voxel_shared.h"

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };

layout(location = 0) in vec3 vGrid[];
layout(location = 1) in vec3 vNormal[];
layout(location = 2) in vec2 vUv[];

layout(location = 0) centroid out vec3 gNormal;
layout(location = 1) centroid out vec2 gUv;
layout(location = 2) flat out int gAxis;     // 0: x, 1: y, 2: z is the projection axis
layout(location = 3) flat out vec4 gPlane;   // swizzled plane: z = plane.x + plane.y*u + plane.z*v
layout(location = 4) flat out vec2 gDepth;   // the triangle's swizzled z range

vec3 swizzle(vec3 p, int axis) {
  return axis == 0 ? p.yzx : (axis == 1 ? p.zxy : p);
}

void main() {
  vec3 n = cross(vGrid[1] - vGrid[0], vGrid[2] - vGrid[0]);
  vec3 a = abs(n);
  int axis = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
  if (!(a[axis] > 0.0)) return;  // degenerate in grid space
  vec3 s0 = swizzle(vGrid[0], axis);
  vec3 s1 = swizzle(vGrid[1], axis);
  vec3 s2 = swizzle(vGrid[2], axis);
  vec3 sn = swizzle(n, axis);
  // z(u, v) on the triangle's plane, for the depth span inside each pixel.
  vec4 plane = vec4(dot(sn, s0) / sn.z, -sn.x / sn.z, -sn.y / sn.z, 0.0);
  vec2 depth = vec2(min(s0.z, min(s1.z, s2.z)), max(s0.z, max(s1.z, s2.z)));
  float res = voxel.gridInfo.x;
  vec3 s[3] = vec3[3](s0, s1, s2);
  for (int i = 0; i < 3; ++i) {
    gNormal = vNormal[i];
    gUv = vUv[i];
    gAxis = axis;
    gPlane = plane;
    gDepth = depth;
    // grid [0, N] -> clip [-1, 1]; depth is not rasterized (no depth attachment)
    gl_Position = vec4(s[i].xy / res * 2.0 - 1.0, 0.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}
