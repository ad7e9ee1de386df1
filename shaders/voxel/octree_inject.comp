#version 450 core
// Direct light injected into the octree's leaves, one invocation per listed voxel.
// Irradiance at the voxel centre, offset along the voxel's normal: punctual lights
// with one shadow ray each; emissive surfaces by their exact unshadowed irradiance
// (emitterFactor) times the visible fraction of shadow rays drawn in proportion to
// it (leafEmitterRay), every emitter sampled in turn when there are few, else
// emitters drawn by power. The leaf's radiance becomes albedo / pi x irradiance
// (Lambertian exitance over pi). A voxel whose normals cancel with no axis to keep
// apart is lit as if it faced each light. A two-sided leaf (octree.glsl, leafAxis)
// is lit twice, once as each side of its axis, into its two light slots.
// Effect-plan variants (scene/effects.h): VOXGI_NO_SHADOWS casts no shadow ray (every
// sample point counts as visible); VOXGI_NO_EMISSION leaves emitters out.
// OCTREE_BVH (rtgi with its BVH bound, rtgi_bvh.glsl's defines): the shadow rays run
// on the scene's exact triangles, from the leaf's own surface where it is found
// there (surfaceBelow), where the light is then taken too. Marched through the
// octree, they meet voxels that stand up to one voxel beyond every surface, so each
// shadow is a voxel wider than its occluder's: the night hall's leaves came out 8%
// darker than the exact light at the points they stand for (with shadows off,
// within 1%).
#include "scene_shared.h"
#include "voxel_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "octree_light.glsl"
#ifdef OCTREE_BVH
#include "rtgi_bvh.glsl"

// Visibility from p along unit l, dist away. From the leaf's own surface, found on
// the triangles (`onSurface`: octree_surface.glsl), an exact shadow ray. Elsewhere p
// stands 1.6 voxels off the leaf's centre, where the surface the leaf holds is known
// only to a voxel: p may sit past a surface nearby (the far face of a wall thinner
// than a voxel, the other side of a corner) and see light the leaf's surface does
// not, so the first kNearFieldVoxels are marched through the octree, whose voxels
// keep it out (the day hall at 64 frames, FLIP 0.071 with them, 0.079 without; the
// sealed room 0.050 against 0.057), and the rest is an exact shadow ray.
float lightVisibleExact(vec3 p, vec3 l, float dist, float start, bool onSurface) {
  if (!onSurface &&
      octreeVisible(p, l, min(dist, kNearFieldVoxels * octreeVoxelSize()), start, 0.0) == 0.0)
    return 0.0;
  return bvhVisible(p, l, dist, false, 0.0);
}

// The same to a random point on emitter e (leafEmitterRay; a cluster's disk lies up
// to its radius behind its facets: bvhVisible's slack).
float emitterVisibleExact(GpuEmitter e, vec3 p, vec3 n, float start, bool onSurface) {
  vec3 l;
  float dist;
  if (!leafEmitterRay(e, p, n, l, dist)) return 0.0;
  if (!(dist > 0.0)) return 1.0;
  float near = min(dist, kNearFieldVoxels * octreeVoxelSize());
  if (!onSurface && octreeVisible(p, l, near, start, 0.0) == 0.0) return 0.0;
  return bvhVisible(p, l, dist, true, emitterSlack(e));
}
#include "octree_surface.glsl"
#endif

layout(local_size_x = kOctreeGroupSize) in;
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };
layout(std430, binding = kOctreeRadianceBinding) buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeMaterialBinding) readonly buffer Material { uvec2 material[]; };
layout(std430, binding = kOctreeDirectBinding) writeonly buffer Direct { uint directOut[]; };

#ifdef VOXGI_NO_SHADOWS
#define LIGHT_VISIBLE(p, l, dist, start) 1.0
#define EMITTER_VISIBLE(e, p, n, start) 1.0
#elif defined(OCTREE_BVH)
#define LIGHT_VISIBLE(p, l, dist, start) lightVisibleExact(p, l, dist, start, onSurface)
#define EMITTER_VISIBLE(e, p, n, start) emitterVisibleExact(e, p, n, start, onSurface)
#else
#define LIGHT_VISIBLE(p, l, dist, start) octreeVisible(p, l, dist, start, 0.0)
#define EMITTER_VISIBLE(e, p, n, start) emitterVisible(e, p, n, start)
#endif

// The irradiance at the voxel centre as seen by a surface of unit normal n (none
// where !oriented); with the BVH, at the leaf's own surface where it is found
// (surfaceBelow, for light slot `slot`), as the bounce rays start there too. From a
// point 1.6 voxels off the centre (what the voxels alone allow), the day hall's
// leaves lit by the sun, the skylight and the lamps came out up to 20% darker than
// their surfaces.
vec3 irradianceAt(vec3 centre, vec3 n, bool oriented, uint slot) {
  // Rays start off the surface; an unoriented voxel starts at its centre and skips
  // its own cell and neighbours by distance instead.
  vec3 p = leafOffPoint(centre, n);
  float start = oriented ? 0.0 : kSurfaceOffsetVoxels;
  bool onSurface = false;
#ifdef OCTREE_BVH
  vec3 q;
  onSurface = oriented && surfaceBelow(centre, n, slot, q);
  if (onSurface) {
    centre = q;
    p = q;
  }
#endif

  vec3 irradiance = vec3(0.0);
  int lightCount = int(octree.light.y);
  for (int k = 0; k < lightCount; ++k) {
    GpuLight light = lights[k];
    vec3 l;
    float dist;
    punctualDirection(light, centre, l, dist);
    float cosine = oriented ? dot(n, l) : 1.0;
    if (cosine <= 0.0) continue;
    // The unshadowed irradiance, with the light's falloff and cone, as the raster
    // baseline computes it for a white Lambertian surface facing the light.
    Surface s;
    s.p = centre;
    s.n = oriented ? n : l;
    s.v = s.n;
    s.diffuse = vec3(1.0);
    s.f0 = vec3(0.0);
    s.alpha = 1.0;
    s.specular = 0.0;
    vec3 e = punctualLight(light, s) * kPi;
    if (all(equal(e, vec3(0.0)))) continue;
    irradiance += e * LIGHT_VISIBLE(p, l, dist, start);
  }

#ifdef VOXGI_NO_EMISSION
  int emitterCount = 0;
#else
  int emitterCount = int(octree.light.z);
#endif
  int rays = int(octree.light.x);
  if (emitterCount > 0 && rays > 0) {
    if (emitterCount <= rays) {
      int perEmitter = rays / emitterCount;
      for (int k = 0; k < emitterCount; ++k) {
        GpuEmitter e = emitters[k];
        float g = oriented ? emitterFactor(e, centre, n)
                           : emitterFactor(e, centre, normalize(emitterCenter(e) - centre));
        if (g <= 0.0) continue;
        float visible = 0.0;
        for (int r = 0; r < perEmitter; ++r) visible += EMITTER_VISIBLE(e, p, n, start);
        irradiance += e.radiance * g * (visible / float(perEmitter));
      }
    } else {
      for (int r = 0; r < rays; ++r) {
        float pmf;
        GpuEmitter e = emitters[pickEmitter(rand01(), emitterCount, pmf)];
        float g = oriented ? emitterFactor(e, centre, n)
                           : emitterFactor(e, centre, normalize(emitterCenter(e) - centre));
        if (g <= 0.0 || pmf <= 0.0) continue;
        irradiance += e.radiance * g * EMITTER_VISIBLE(e, p, n, start) / (pmf * float(rays));
      }
    }
  }
  return irradiance;
}

void main() {
  uint i = octreeInvocation();
  if (i >= octree.pass.z) return;
  uint code = voxels[octree.slice.x + i];
  ivec3 v = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  int depth = octreeDepth();
  uint node = 0u;
  for (int l = 0; l < depth; ++l) node = octreeNodes[node] + childIndex(v, depth, l);
  rngState = pcgHash(pcgHash(octree.pass.w) ^ code);

  uvec2 m = material[node];
  vec4 albedo = unpackUnorm4x8(m.x);
  vec3 n = leafNormal(m.y);
  bool oriented = dot(n, n) > 0.25;
  n = oriented ? normalize(n) : vec3(0.0);
  vec3 centre = octreeToWorld(vec3(v) + 0.5);
  int axis = leafAxis(m.y);
  for (int side = 0; side < (axis >= 0 ? 2 : 1); ++side) {
    if (axis >= 0) n = sideNormal(axis, side == 1);
    uint slot = side == 0 ? node : backSlot(m.y);
    vec3 direct = albedo.rgb / kPi * irradianceAt(centre, n, oriented || axis >= 0, slot);
    uint word = packRgb9e5(direct);
    radiance[slot] = word;
    if (octree.light.w != 0u) directOut[slot] = word;  // bounces follow
  }
}
