#version 450 core
// One more bounce of diffuse light between the octree's leaves, one invocation per
// listed voxel: cosine-distributed rays from the voxel (uniform over the sphere
// where its normals cancel: averaged over orientations, E / pi is the sphere's mean
// radiance too) pick up the radiance of the leaves they hit, as left by
// the previous bounce (a separate buffer: the result does not depend on the order
// threads run in). A two-sided leaf (octree.glsl, leafAxis) gathers once for each
// side of its axis. The leaf's radiance becomes its direct light plus albedo x the
// mean of what the rays brought (cosine sampling: E / pi = mean radiance). Rays that
// leave the grid see no light (the background emits nothing).
// OCTREE_BVH (rtgi with its BVH bound): the rays find their hit on the scene's exact
// triangles, and the leaf that stands for it there (rtgi_voxel_light.glsl, voxelAt)
// gives its light. An oriented leaf's rays start on its own surface, found on the
// triangles (surfaceBelow); the others' start off the centre, and their first
// kNearFieldVoxels are still marched (hitLeaf). Marched
// all the way, a ray stops at the first voxel it touches, and voxels stand up to a
// voxel beyond their surfaces: rays that pass by an edge stop at it. The night
// hall's second bounce against the path tracer's: 0.85 marched, 0.93 with these and
// exact shadow rays (0.97-1.01 in most 16x16 blocks; the mirror ball's blocks, whose
// reflections this term leaves out, hold the rest).
// The first estimate's chain (Octree::estimate, octree.rays.x): its first bounce
// records each ray's light slot and factor (kOctreeRaysRecorded), and the later
// bounces read the previous bounce's light there again, tracing nothing
// (kOctreeRaysReplayed).
#include "scene_shared.h"
#include "voxel_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"

layout(local_size_x = kOctreeGroupSize) in;
layout(std430, binding = kVoxelListBinding) readonly buffer List { uint voxels[]; };
layout(std430, binding = kOctreeRadianceBinding) writeonly buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeMaterialBinding) readonly buffer Material { uvec2 material[]; };
layout(std430, binding = kOctreeScratchBinding) readonly buffer Previous { uint previous[]; };
layout(std430, binding = kOctreeDirectBinding) readonly buffer Direct { uint directIn[]; };
// The rays of the first estimate's chain, recorded by its first bounce and read again
// by the later ones (Octree::estimate): ray r of side `side` of the i-th listed
// voxel at (i * 2 + side) * rays + r, the light slot it read (kOctreeNoSurface:
// none) and its factor (rgb9e5).
layout(std430, binding = kOctreeReplayBinding) buffer Replay { uvec2 replay[]; };
#ifdef OCTREE_BVH
#include "rtgi_bvh.glsl"
#define RTGI_VOXEL_AT_ONLY
#include "rtgi_voxel_light.glsl"
#include "octree_surface.glsl"

// The leaf the ray from p along unit dir brings the light of: with `nearField`, the
// first voxel within kNearFieldVoxels (where p's place about the surface is known
// only to a voxel, as in octree_inject.comp); else, or if none, the leaf that stands
// for the nearest triangle (-1: none, or no hit).
// `scale`: what turns the leaf's light into the light of the triangle met
// (leafToHit); 1 for a marched hit, which meets no triangle.
int hitLeaf(vec3 p, vec3 dir, float start, bool nearField, out vec3 scale) {
  scale = vec3(1.0);
  if (nearField) {
    MarchHit h = octreeTrace(octreeWorldRay(p, dir, kNearFieldVoxels), start, kRaySteps);
    if (h.hit) return int(h.node);
  }
  float t;
  uint tri;
  vec2 bc;
  loopBudget = kPtLoopBudget;
  if (!trace(p, dir, kInf, false, t, tri, bc)) return -1;
  ivec3 cell;
  int leaf = voxelAtCell(p, dir, t, cell);
  if (leaf < 0) return -1;
  uint word = material[leaf].y;
  uint slot = lightSlot(uint(leaf), word, -dir);
  if (surfaces[slot] == kOctreeNoSurface) {
    // The side's surface was looked for under its centre and not found: its light
    // was taken 1.6 voxels or more off the centre (octree_inject.comp). Where slabs
    // thinner than a voxel meet, that point can lie outside a closed room while the
    // leaf faces into it, and hold the light outside: it is read only if the hit sees
    // that point (RtgiTest.ClosedWallsDoNotLeakLight failed with a first chain of 12;
    // not reading such sides at all left the night hall 0.4% darker).
    int axis = leafAxis(word);
    vec3 n = axis >= 0 ? sideNormal(axis, slot != uint(leaf)) : normalize(leafNormal(word));
    vec3 lightPoint = leafOffPoint(octreeToWorld(vec3(cell) + 0.5), n);
    vec3 from = p + dir * (t - bvhEpsilon());
    vec3 d = lightPoint - from;
    float dist = length(d);
    if (dist > 0.0 && bvhVisible(from, d / dist, dist, false, 0.0) == 0.0) return -1;
  }
  scale = leafToHit(uint(leaf), hitBaseColor(tri, bc));
  return leaf;
}
#endif

// The mean radiance the rays bring to the voxel centre as seen by a surface of unit
// normal n (over the sphere where !oriented); a two-sided leaf they hit shows the
// side that faces them (lightSlot).
//
// Where they start. Without the triangles, from 1.6 voxels or more off the centre
// along n (leafRayOffset), clear of the voxels of the leaf's own surface, which
// stand up to a voxel beyond it. That point sees the room from above the surface it
// stands for, and what it gathers depends on how far above: on the validation set's
// gallery view, rtgi's image came out 1.0% too bright from there (and 1.7% too dark
// from 0.6 voxels), in light the pixels' exact first bounce had right (0.993-1.000
// against the path tracer cut at that depth). With OCTREE_BVH an oriented leaf's
// rays start on its surface itself (surfaceBelow) and run on the exact triangles
// from there, as the pixels' rays do: the gallery's mean 1.0098 -> 0.9967 (16
// frames), and FLIP at 64 frames lower on 9 of the set's 10 views.
vec3 gatheredAt(vec3 centre, vec3 n, bool oriented, uint slot, uint record) {
  int rays = int(octree.light.x);
  vec3 gathered = vec3(0.0);
  uint mode = octree.rays.x;
  if (mode == kOctreeRaysReplayed) {
    for (int r = 0; r < rays; ++r) {
      uvec2 hit = replay[record + uint(r)];
      if (hit.x != kOctreeNoSurface)
        gathered += unpackRgb9e5(hit.y) * unpackRgb9e5(previous[hit.x]);
    }
    return gathered / float(max(rays, 1));
  }
  vec3 p = leafOffPoint(centre, n);
  float start = oriented ? 0.0 : kSurfaceOffsetVoxels;
#ifdef OCTREE_BVH
  vec3 onSurface;
  bool exact = oriented && surfaceBelow(centre, n, slot, onSurface);
  if (exact) p = onSurface;
#endif

  for (int r = 0; r < rays; ++r) {
    vec2 u = vec2(rand01(), rand01());
    vec3 dir;
    if (oriented) {
      dir = cosineSample(n, u);
    } else {
      float z = 1.0 - 2.0 * u.x;
      float s = sqrt(max(0.0, 1.0 - z * z));
      dir = vec3(s * cos(2.0 * kPi * u.y), s * sin(2.0 * kPi * u.y), z);
    }
#ifdef OCTREE_BVH
    vec3 scale;
    int leaf = hitLeaf(p, dir, start, !exact, scale);
    bool hit = leaf >= 0;
    uint hitNode = uint(max(leaf, 0));
#else
    MarchHit h = octreeTrace(octreeWorldRay(p, dir, 3.0e38), start, kRaySteps);
    bool hit = h.hit;
    uint hitNode = h.node;
    const vec3 scale = vec3(1.0);
#endif
    uint word = hit ? material[hitNode].y : 0u;
    uint read =
        hit && !seenFromBehind(word, dir) ? lightSlot(hitNode, word, -dir) : kOctreeNoSurface;
    if (read != kOctreeNoSurface) gathered += scale * unpackRgb9e5(previous[read]);
    if (mode == kOctreeRaysRecorded) replay[record + uint(r)] = uvec2(read, packRgb9e5(scale));
  }
  return gathered / float(max(rays, 1));
}

void main() {
  uint i = octreeInvocation();
  if (i >= octree.pass.z) return;
  uint code = voxels[octree.slice.x + i];
  ivec3 v = ivec3(code & 1023u, (code >> 10) & 1023u, (code >> 20) & 1023u);
  int depth = octreeDepth();
  uint node = 0u;
  for (int l = 0; l < depth; ++l) node = octreeNodes[node] + childIndex(v, depth, l);
  rngState = pcgHash(pcgHash(octree.pass.w + 7919u * octree.light.w) ^ code);

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
    uint record = (i * 2u + uint(side)) * octree.light.x;
    vec3 gathered = gatheredAt(centre, n, oriented || axis >= 0, slot, record);
    vec3 direct = unpackRgb9e5(directIn[slot]);
    radiance[slot] = packRgb9e5(direct + albedo.rgb * gathered);
  }
}
