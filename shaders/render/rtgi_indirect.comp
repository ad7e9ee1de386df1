#version 450 core
// rtgi stage "indirect": one cosine-distributed ray per pixel and frame through the
// octree; the leaf it hits (unless seen from behind: seenFromBehind) gives the diffuse radiance it reflects (its injected
// direct light plus the voxel bounces, bounces - 1 of them), so the pixel sees
// `bounces` bounces in all. Emission of the voxels hit is left out: light from
// emitters reaches the pixel through the shadows stage (no double counting).
// Cosine sampling: the Lambertian estimate is albedo x L.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "octree_light.glsl"
#define RTGI_PIXEL_LIST
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiTraceGroup) in;

layout(std430, binding = kOctreeRadianceBinding) readonly buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeMaterialBinding) readonly buffer Material { uvec2 material[]; };
layout(binding = kIndirectImage, rgba16f) uniform writeonly image2D indirectOut;

void main() {
  ivec2 px;
  if (!tracePixel(px)) return;
  Pixel p = loadPixel(px);
  vec3 result = vec3(0.0);
  if (p.covered && any(greaterThan(p.s.diffuse, vec3(0.0)))) {
    seedPixel(px, 2u);
    vec3 dir = cosineSample(p.s.n, vec2(rand01(), rand01()));
    // A ray below the surface itself (a normal map tilts n) brings nothing: no leaks.
    bool above = !belowSurface(px, dir);
    MarchHit h = octreeTrace(octreeWorldRay(surfaceRayOrigin(px, p.s), dir, 3.0e38), 0.0, kRaySteps);
    if (above && h.hit && !seenFromBehind(material[h.node].y, dir))
      result = p.s.diffuse * unpackRgb9e5(radiance[h.node]);
  }
  imageStore(indirectOut, px, vec4(result, 1.0));
}
