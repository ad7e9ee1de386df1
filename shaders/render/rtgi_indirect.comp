#version 450 core
// rtgi stage "indirect": one cosine-distributed ray per pixel and frame; the surface
// it meets gives the diffuse radiance it reflects, read from the voxels' light (its
// injected direct light plus the voxel bounces, bounces - 1 of them), so the pixel
// sees `bounces` bounces in all. Emission of the surface hit is left out: light from
// emitters reaches the pixel through the shadows stage (no double counting).
// Cosine sampling: the Lambertian estimate is albedo x L.
//
// RTGI_BVH: the ray finds its hit on the exact triangles (rtgi_bvh.glsl), and the
// voxels serve only as the light cache at that point (rtgi_voxel_light.glsl). Without it
// (--voxel-rays, or an animated scene) the ray marches the octree and the first leaf
// it meets (unless seen from behind: seenFromBehind) both stops it and lights it;
// voxels are fatter than the surfaces, so near a contact they stop rays that would
// have passed (the floor under a sphere comes out too dark).
//
// RTGI_CONES (--indirect cones): instead of the ray, six cones through the octree's
// filtered levels (rtgi_cones.glsl), the same light every frame.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "octree_light.glsl"
#define RTGI_PIXEL_LIST
#include "rtgi_common.glsl"
#ifdef RTGI_BVH
#include "rtgi_bvh.glsl"
#endif

layout(local_size_x = kRtgiTraceGroup) in;

layout(std430, binding = kOctreeRadianceBinding) readonly buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeMaterialBinding) readonly buffer Material { uvec2 material[]; };
layout(binding = kIndirectImage, rgba16f) uniform writeonly image2D indirectOut;

#ifdef RTGI_BVH
#include "rtgi_voxel_light.glsl"
#endif
#ifdef RTGI_CONES
#include "rtgi_cones.glsl"
#endif

void main() {
  ivec2 px;
  if (!tracePixel(px)) return;
  Pixel p = loadPixel(px);
  vec3 result = vec3(0.0);
  if (p.covered && any(greaterThan(p.s.diffuse, vec3(0.0)))) {
#ifdef RTGI_CONES
    result = p.s.diffuse * coneIrradiance(surfaceRayOrigin(px, p.s), p.s.n, surfaceNormal(px));
#else
    seedPixel(px, 2u);
    vec3 dir = cosineSample(p.s.n, vec2(rand01(), rand01()));
    // A ray below the surface itself (a normal map tilts n) brings nothing: no leaks.
    vec3 ng = surfaceNormal(px);
    if (dot(dir, ng) >= 0.0) {
#ifdef RTGI_BVH
      vec3 o = p.s.p + (ng != vec3(0.0) ? ng : p.s.n) * bvhEpsilon();
      result = p.s.diffuse * voxelLightAlong(o, dir);
#else
      MarchHit h =
          octreeTrace(octreeWorldRay(surfaceRayOrigin(px, p.s), dir, 3.0e38), 0.0, kRaySteps);
      if (h.hit && !seenFromBehind(material[h.node].y, dir))
        result = p.s.diffuse * unpackRgb9e5(radiance[h.node]);
#endif
    }
#endif
  }
  imageStore(indirectOut, px, vec4(result, 1.0));
}
