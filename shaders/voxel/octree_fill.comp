#version 450 core
// Octree leaves, one invocation per listed voxel: mark the leaf occupied and copy
// the resolved voxel into it (radiance starts at zero).
#define OCTREE_NODES_WRITABLE
#include "voxel_shared.h"
#include "octree.glsl"

layout(local_size_x = kOctreeGroupSize) in;
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };
layout(std430, binding = kOctreeRadianceBinding) writeonly buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeMaterialBinding) writeonly buffer Material { uvec2 material[]; };
layout(std430, binding = kOctreeEmissionBinding) writeonly buffer Emission { uint emission[]; };
layout(binding = kAlbedoTexUnit) uniform sampler3D albedoGrid;
layout(binding = kNormalTexUnit) uniform sampler3D normalGrid;
layout(binding = kEmissionTexUnit) uniform sampler3D emissionGrid;

void main() {
  uint i = octreeInvocation();
  if (i >= octree.pass.z) return;
  uint code = voxels[i];
  ivec3 v = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  int depth = octreeDepth();
  uint node = 0u;
  for (int l = 0; l < depth; ++l) node = octreeNodes[node] + childIndex(v, depth, l);
  octreeNodes[node] = kOctreeLeafOccupied;
  vec4 a = texelFetch(albedoGrid, v, 0);
  vec4 n = texelFetch(normalGrid, v, 0);
  vec4 e = texelFetch(emissionGrid, v, 0);
  material[node] = uvec2(packUnorm4x8(a), packSnorm4x8(vec4(n.xyz, 0.0)));
  emission[node] = packRgb9e5(e.rgb);
  radiance[node] = 0u;
}
