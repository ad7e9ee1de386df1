#version 450 core
// Inner nodes of one level from their 8 children, one invocation per node of the
// level: opacity is the children's mean (an empty child counts 0); radiance,
// albedo, emission and normals are opacity-weighted means: a normal's length says how
// far the children's agree (1: one side, 0: they cancel, as both sides of a wall
// do; the cone tracer, rtgi_cones.glsl, tells them apart). The cone tracer composites
// colour x opacity front to back, so a half-empty node weighs half.
// OCTREE_FILTER_RADIANCE: radiance only (the refinement of a built octree, whose
// materials and emission do not change).
#include "octree.glsl"

layout(local_size_x = kOctreeGroupSize) in;
layout(std430, binding = kOctreeRadianceBinding) buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeMaterialBinding) buffer Material { uvec2 material[]; };
layout(std430, binding = kOctreeEmissionBinding) buffer Emission { uint emission[]; };

void main() {
  uint i = octreeInvocation();
  if (i >= octree.pass.z) return;
  uint node = octree.pass.y + i;
  uint first = octreeNodes[node];
  if (first == 0u) return;
  vec3 rad = vec3(0.0), alb = vec3(0.0), em = vec3(0.0), nrm = vec3(0.0);
  float opacity = 0.0;
  for (uint c = 0u; c < 8u; ++c) {
    uvec2 m = material[first + c];
    vec4 a = unpackUnorm4x8(m.x);
    float w = a.a;
    vec3 r = unpackRgb9e5(radiance[first + c]);
    // A two-sided leaf's sides (octree.glsl, leafAxis): cones see both.
    if (leafAxis(m.y) >= 0) r = 0.5 * (r + unpackRgb9e5(radiance[backSlot(m.y)]));
    rad += r * w;
    opacity += w;
#ifndef OCTREE_FILTER_RADIANCE
    alb += a.rgb * w;
    em += unpackRgb9e5(emission[first + c]) * w;
    nrm += leafNormal(m.y) * w;
#endif
  }
  float inv = opacity > 0.0 ? 1.0 / opacity : 0.0;
  radiance[node] = packRgb9e5(rad * inv);
#ifndef OCTREE_FILTER_RADIANCE
  material[node] =
      uvec2(packUnorm4x8(vec4(alb * inv, opacity / 8.0)), packSnorm4x8(vec4(nrm * inv, 0.0)));
  emission[node] = packRgb9e5(em * inv);
#endif
}
