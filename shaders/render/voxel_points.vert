#version 450 core
// Voxels as cubes (the debug view of the voxel pipeline): one instance per
// occupied voxel, 36 vertices from gl_VertexID, no vertex buffer.
// voxel grid -> scene space -> clip space.
#include "scene_shared.h"
#include "voxel_shared.h"

layout(std140, binding = kFrameBinding) uniform FrameBlock { GpuFrame frame; };
layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };
layout(std430, binding = kVoxelAttribBinding) readonly buffer Attributes { uvec4 attributes[]; };

layout(location = 0) flat out vec3 vAlbedo;
layout(location = 1) flat out vec3 vEmission;
layout(location = 2) flat out vec3 vFaceNormal;
layout(location = 3) out vec3 vPosition;

// Each face: the axis it faces and its two triangles as corner bits (x=1, y=2, z=4).
const int kCorners[36] = int[36](1, 3, 7, 1, 7, 5,   // +x
                                 0, 4, 6, 0, 6, 2,   // -x
                                 2, 6, 7, 2, 7, 3,   // +y
                                 0, 1, 5, 0, 5, 4,   // -y
                                 4, 5, 7, 4, 7, 6,   // +z
                                 0, 2, 3, 0, 3, 1);  // -z
const vec3 kNormals[6] = vec3[6](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0),
                                 vec3(0, 0, 1), vec3(0, 0, -1));

void main() {
  uint code = voxels[gl_InstanceID];
  ivec3 v = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  int corner = kCorners[gl_VertexID];
  vec3 local = vec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
  vPosition = voxel.gridOrigin.xyz + (vec3(v) + local) * voxel.gridOrigin.w;
  uvec4 a = attributes[gl_InstanceID];
  vAlbedo = unpackUnorm4x8(a.x).rgb;
  vEmission = vec3(unpackHalf2x16(a.z), unpackHalf2x16(a.w).x);
  vFaceNormal = kNormals[gl_VertexID / 6];
  mat4 viewProj = mat4(frame.viewProj[0], frame.viewProj[1], frame.viewProj[2], frame.viewProj[3]);
  gl_Position = viewProj * vec4(vPosition, 1.0);
}
