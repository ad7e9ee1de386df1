#version 450 core
// rtgi stage "indirect": one cosine-distributed ray per pixel and frame; the surface
// it meets gives the diffuse radiance it reflects, read from the voxels' light (its
// injected direct light plus the voxel bounces, bounces - 1 of them), so the pixel
// sees `bounces` bounces in all. Emission of the surface hit is left out: light from
// emitters reaches the pixel through the shadows stage (no double counting).
// Cosine sampling: the Lambertian estimate is albedo x L.
//
// RTGI_BVH: the ray finds its hit on the exact triangles (rtgi_bvh.glsl), and the
// voxels serve only as the light cache at that point (voxelLightAt). Without it
// (--voxel-rays, or an animated scene) the ray marches the octree and the first leaf
// it meets (unless seen from behind: seenFromBehind) both stops it and lights it;
// voxels are fatter than the surfaces, so near a contact they stop rays that would
// have passed (the floor under a sphere comes out too dark).
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
// The voxels' light where the ray from o along unit dir meets a triangle, t world
// units away: the first leaf about that point that faces the ray, marched from half
// a voxel before the point to one past it. A leaf seen from behind there belongs to
// another surface at a contact (the floor's own voxels under a sphere), or to the
// back of the one hit; it is passed over. None: no light (a surface without voxels,
// or the inside of a closed one).
vec3 voxelLightAt(vec3 o, vec3 dir, float t) {
  float tv = t / octreeVoxelSize();
  MarchRay r = octreeWorldRay(o, dir, tv + 1.0);
  float start = max(tv - 0.5, 0.0);
  for (int k = 0; k < 3; ++k) {
    MarchHit h = octreeTrace(r, start, 8);
    if (!h.hit) break;
    if (!seenFromBehind(material[h.node].y, dir)) return unpackRgb9e5(radiance[h.node]);
    // On past the leaf: where the ray leaves its cell.
    vec3 far = vec3(h.voxel) + max(vec3(r.stepDir), vec3(0.0));
    vec3 tf = mix(vec3(kMarchInf), (far - r.o) * r.invD, notEqual(r.stepDir, ivec3(0)));
    start = min(min(tf.x, tf.y), tf.z) + 1e-4;
  }
  return vec3(0.0);
}
#endif

void main() {
  ivec2 px;
  if (!tracePixel(px)) return;
  Pixel p = loadPixel(px);
  vec3 result = vec3(0.0);
  if (p.covered && any(greaterThan(p.s.diffuse, vec3(0.0)))) {
    seedPixel(px, 2u);
    vec3 dir = cosineSample(p.s.n, vec2(rand01(), rand01()));
    // A ray below the surface itself (a normal map tilts n) brings nothing: no leaks.
    vec3 ng = surfaceNormal(px);
    if (dot(dir, ng) >= 0.0) {
#ifdef RTGI_BVH
      vec3 o = p.s.p + (ng != vec3(0.0) ? ng : p.s.n) * bvhEpsilon();
      float t;
      uint tri;
      vec2 bc;
      loopBudget = kPtLoopBudget;
      if (trace(o, dir, kInf, false, t, tri, bc)) result = p.s.diffuse * voxelLightAt(o, dir, t);
#else
      MarchHit h =
          octreeTrace(octreeWorldRay(surfaceRayOrigin(px, p.s), dir, 3.0e38), 0.0, kRaySteps);
      if (h.hit && !seenFromBehind(material[h.node].y, dir))
        result = p.s.diffuse * unpackRgb9e5(radiance[h.node]);
#endif
    }
  }
  imageStore(indirectOut, px, vec4(result, 1.0));
}
