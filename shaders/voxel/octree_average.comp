#version 450 core
// Voxel light that converges: blends this estimate of the leaves' radiance into the
// running mean, one invocation per listed voxel of the estimate's slice. The estimate
// (Scratch) is rgb9e5, the mean (Mean) is float; the mean is published into the
// radiance the tracers read, in rgb9e5. octree.blend.x is this estimate's weight
// over the weights of all so far (Octree::refine: they grow with the rays so far),
// 1 for the first, so noise falls about as 1 / sqrt(estimates), as a pixel's does.
// Beside it (octree.blend.z: Octree::Settings::keepBounces), the mean of the estimate
// less its direct light (Bounce): the voxel bounces alone, for rtgi's rays that light
// their hit exactly (rtgi_indirect.comp). A two-sided leaf (octree.glsl, leafAxis)
// blends both its slots.
// Not clamped at 0: the two rgb9e5 values round apart, and the mean averages that out.
#include "voxel_shared.h"
#include "octree.glsl"

layout(local_size_x = kOctreeGroupSize) in;
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };
layout(std430, binding = kOctreeRadianceBinding) writeonly buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeScratchBinding) readonly buffer Estimate { uint estimate[]; };
layout(std430, binding = kOctreeMeanBinding) buffer Mean { vec4 mean[]; };
layout(std430, binding = kOctreeDirectBinding) readonly buffer Direct { uint direct[]; };
layout(std430, binding = kOctreeBounceBinding) buffer Bounce { vec4 bounce[]; };
layout(std430, binding = kOctreeMaterialBinding) readonly buffer Material { uvec2 material[]; };

void blendSlot(uint slot) {
  vec3 sampled = unpackRgb9e5(estimate[slot]);
  float w = octree.blend.x;
  vec3 m = w >= 1.0 ? sampled : mean[slot].rgb + (sampled - mean[slot].rgb) * w;
  mean[slot] = vec4(m, 0.0);
  radiance[slot] = packRgb9e5(m);
  if (octree.blend.z < 0.5) return;
  vec3 b = octree.blend.y > 0.5 ? sampled - unpackRgb9e5(direct[slot]) : vec3(0.0);
  bounce[slot] = vec4(w >= 1.0 ? b : bounce[slot].rgb + (b - bounce[slot].rgb) * w, 0.0);
}

void main() {
  uint i = octreeInvocation();
  if (i >= octree.pass.z) return;
  uint code = voxels[octree.slice.x + i];
  ivec3 v = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  int depth = octreeDepth();
  uint node = 0u;
  for (int l = 0; l < depth; ++l) node = octreeNodes[node] + childIndex(v, depth, l);
  blendSlot(node);
  uint word = material[node].y;
  if (leafAxis(word) >= 0) blendSlot(backSlot(word));  // two-sided
}
