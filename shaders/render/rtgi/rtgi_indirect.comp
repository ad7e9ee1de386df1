#version 450 core
// rtgi stage "indirect": one cosine-distributed ray per pixel and frame; the surface
// it meets gives the diffuse radiance it reflects, read from the voxels' light (its
// injected direct light plus the voxel bounces, bounces - 1 of them), so the pixel
// sees `bounces` bounces in all. Emission of the surface hit is left out: light from
// emitters reaches the pixel through the shadows stage (no double counting).
// Cosine sampling: the Lambertian estimate is albedo x L. A rough dielectric (a glTF
// material the specular stage skips) draws its ray from the path tracer's BSDF
// instead, weighed by BSDF x cosine / pdf.
//
// RTGI_BVH: the ray finds its hit on the exact triangles (rtgi_bvh.glsl), which is
// shaded as the path tracer would shade it: its exact direct light (the shadows
// stage's estimators, rtgi_direct_light.glsl, with shadow rays through the BVH) plus
// the voxel bounces alone at that point (the voxels' light less their direct light,
// rtgi_voxel_light.glsl), so the voxels serve only as the light cache for the
// bounces beyond the first. Their direct light would carry light through a wall
// thinner than a voxel (its other side lit the same voxel) and blur shadows to the
// voxels' size. A mirror hit keeps its diffuse part only (its highlight from a light
// would be a firefly for a cosine ray; the path tracer reaches it by the mirror's
// own reflection, which this ray does not follow). A pixel's first sample (none in
// its mean yet: the first frame, a disocclusion, a sparse start) reads the voxels'
// whole light at the hit instead, direct light included: cheap and smooth where one
// exact sample's noise outweighs the voxels' bias, which then fades from the mean as
// 1/samples. Without it
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

float shadowRay(vec3 o, vec3 l, float dist, bool toEmitter, float slack) {
  return bvhVisible(o, l, dist, toEmitter, slack);
}

#include "rtgi_direct_light.glsl"
#include "rtgi_hit.glsl"
layout(std430, binding = kOctreeBounceBinding) readonly buffer Bounce { vec4 bounce[]; };
#include "rtgi_sample_count.glsl"
#endif

layout(local_size_x = kRtgiTraceGroup) in;

layout(std430, binding = kOctreeRadianceBinding) readonly buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeMaterialBinding) readonly buffer Material { uvec2 material[]; };
layout(binding = kIndirectImage, rgba16f) uniform writeonly image2D indirectOut;

#ifdef RTGI_BVH
#include "rtgi_voxel_light.glsl"

// Whether leaf `node` can stand for the light leaving the side of a surface whose
// normal is ng: a leaf whose normal follows ng. Not a two-sided one (its faces
// cancel: a wall thinner than a voxel; its slot on ng's side, octree.glsl leafAxis,
// holds that side's light, but going on comes closer to the path tracer: the night
// hall at 64 frames 0.063 against 0.068 reading it), nor one turned away (the other
// side's faces outweigh this side's).
bool voxelStandsFor(int node, vec3 ng) {
  if (node < 0) return false;
  vec3 n = leafNormal(material[node].y);
  float len2 = dot(n, n);
  return len2 > 0.25 && dot(n, ng) > 0.5 * sqrt(len2);
}

// Radiance arriving at o from unit direction dir: the nearest triangle's exact direct
// light plus the voxel bounces there (its emission comes through the shadows stage).
// With every bounce in the voxels (kRtgiAllBounces), where the hit's voxel cannot
// stand for its side (voxelStandsFor), the path goes on instead: one more cosine ray
// from the hit, lit the same way, up to kMaxIndirectVertices hits; the voxel bounces
// of the last one count whatever its voxel.
vec3 hitRadiance(vec3 o, vec3 dir) {
  loopBudget = kPtLoopBudget;
  bool goOn = (rtgi.flags & kRtgiAllBounces) != 0u;
  vec3 throughput = vec3(1.0);
  vec3 result = vec3(0.0);
  for (int k = 0; k < kMaxIndirectVertices; ++k) {
    TriangleHit h;
    if (!traceSurface(o, dir, h)) break;
    int node = voxelAt(o, dir, h.t);
    bool mirror = h.roughness < kMirrorRoughness;
    if (mirror) h.s.specular = 0.0;
    vec3 from = h.s.p + h.ng * bvhEpsilon();
    result += throughput * directLight(h.s, from, h.below);
    // The bounces arrive from all about: the material's directional albedo, not the
    // voxels' Lambert (voxelToMaterial).
    vec3 albedo = directionalAlbedo(h.s, h.roughness);
    vec3 toMaterial = voxelToMaterial(h.s, h.roughness, h.base);
    if (!goOn || k + 1 == kMaxIndirectVertices || voxelStandsFor(node, h.ng)) {
      if (node >= 0)
        result += throughput * toMaterial * leafToHit(uint(node), h.base) *
                  max(bounce[lightSlot(uint(node), material[node].y, h.ng)].rgb, vec3(0.0));
      break;
    }
    if (!any(greaterThan(albedo, vec3(0.0)))) break;
    dir = cosineSample(h.s.n, vec2(rand01(), rand01()));
    if (dot(dir, h.ng) <= 0.0 || dot(dir, h.below) < 0.0) break;
    throughput *= albedo;
    o = from;
  }
  return result;
}
#endif
#ifdef RTGI_CONES
#include "rtgi_cones.glsl"
#endif

// A glTF material the specular stage skips (isSpecular: a dielectric of roughness
// kGlossyRoughness and up) that is not pure Lambert.
bool roughDielectric(Pixel p) {
  return !isSpecular(p.metallic, p.roughness) && !isLambertian(p.metallic, p.roughness);
}

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
    vec3 dir;
    vec3 weight = p.s.diffuse;  // the BSDF x cosine / pdf of the direction drawn
    if (roughDielectric(p)) {
      // The specular stage leaves it out: the whole BSDF here, drawn as the path
      // tracer draws it (its GGX lobe and the Lambert part less what Fresnel takes).
      Bsdf b = makeBsdf(p.base, p.metallic, p.roughness, max(dot(p.s.n, p.s.v), 1e-4));
      vec2 u = vec2(rand01(), rand01());
      if (rand01() >= b.specularChance) {
        dir = cosineSample(p.s.n, u);
      } else {
        vec3 t, bt;
        basis(p.s.n, t, bt);
        vec3 ve = vec3(dot(p.s.v, t), dot(p.s.v, bt), dot(p.s.v, p.s.n));
        vec3 m = sampleVndf(ve, b.alpha, u);
        dir = reflect(-p.s.v, normalize(t * m.x + bt * m.y + p.s.n * m.z));
      }
      float pdf;
      vec3 f = evalBsdf(b, p.s.n, p.s.v, dir, pdf);
      weight = pdf > 0.0 ? f / pdf : vec3(0.0);
    } else {
      dir = cosineSample(p.s.n, vec2(rand01(), rand01()));
    }
    // A ray below the surface itself (a normal map tilts n) brings nothing: no leaks.
    vec3 ng = surfaceNormal(px);
    if (dot(dir, ng) >= 0.0 && any(greaterThan(weight, vec3(0.0)))) {
#ifdef RTGI_BVH
      vec3 o = p.s.p + (ng != vec3(0.0) ? ng : p.s.n) * bvhEpsilon();
      result = weight * (samplesSoFar(px) < 1.0 ? voxelLightAlong(o, dir) : hitRadiance(o, dir));
#else
      MarchHit h =
          octreeTrace(octreeWorldRay(surfaceRayOrigin(px, p.s), dir, 3.0e38), 0.0, kRaySteps);
      uint word = h.hit ? material[h.node].y : 0u;
      if (h.hit && !seenFromBehind(word, dir))
        result = weight * unpackRgb9e5(radiance[lightSlot(h.node, word, -dir)]);
#endif
    }
#endif
  }
  imageStore(indirectOut, px, vec4(result, 1.0));
}
