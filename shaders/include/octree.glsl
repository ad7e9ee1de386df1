// The octree as shaders read it: bindings, the shared traversal (octree_march.h),
// and helpers in world (scene-relative) space. A shader that writes the nodes
// defines OCTREE_NODES_WRITABLE before including this.
#ifndef VOXGI_OCTREE_GLSL
#define VOXGI_OCTREE_GLSL

#include "octree_shared.h"
#include "nonfinite.glsl"

layout(std140, binding = kOctreeParamsBinding) uniform OctreeBlock { OctreeParams octree; };
#ifdef OCTREE_NODES_WRITABLE
layout(std430, binding = kOctreeNodeBinding) coherent buffer OctreeNodes { uint octreeNodes[]; };
#define VOXGI_NODE(i) octreeNodes[i]
#else
layout(std430, binding = kOctreeNodeBinding) readonly buffer OctreeNodes { uint octreeNodes[]; };
// The same words as a buffer texture: the traversal reads them this way.
layout(binding = kOctreeNodeTexUnit) uniform usamplerBuffer octreeNodeTex;
#define VOXGI_NODE(i) texelFetch(octreeNodeTex, int(i)).x
#endif

#include "octree_march.h"

// Cells one ray may visit; past them a shadow ray counts as unoccluded and
// other rays as escaped.
const int kRaySteps = 1024;
// Rays leave a surface this many voxels along its normal, so they do not hit the
// voxels of the surface they start from; and stop short of an emitter by as much,
// so they do not hit the voxels of the light they aim at.
const float kSurfaceOffsetVoxels = 1.5;

// How far from a leaf's ray origin (voxels) the octree's passes march the voxels
// before they trust rays on the exact triangles (OCTREE_BVH): the origin's place
// about the surface is known only to a voxel (octree_inject.comp,
// lightVisibleExact).
const float kNearFieldVoxels = 2.0;

// How far along a surface's unit normal n the voxels it touches reach: a voxel
// touches the plane when its centre is within this support of it (half the cube's
// extent along n, in voxels: 0.5 for an axis-aligned plane, 0.87 for a diagonal
// one), and so reaches at most twice it past the plane.
float voxelSupport(vec3 n) { return 0.5 * (abs(n.x) + abs(n.y) + abs(n.z)); }
// Where rays leave a surface point along n (voxels): past every voxel the surface
// touches, which is kSurfaceOffsetVoxels for an axis-aligned plane and more for an
// oblique one (a sphere's voxels would otherwise shadow its own rays).
float surfaceRayOffset(vec3 n) { return max(kSurfaceOffsetVoxels, 2.0 * voxelSupport(n) + 0.1); }
// The same from a voxel's centre, which may lie up to one support off the surface.
float leafRayOffset(vec3 n) { return max(kSurfaceOffsetVoxels, 3.0 * voxelSupport(n) + 0.1); }

// Two-sided leaves. A leaf whose normals cancel (both faces of a wall thinner than
// a voxel) holds two surfaces facing apart. Its light is kept apart on the two sides
// of the axis its normals lie along (the resolve's second moments: voxelMoments):
// the + side in the light buffers' slot `node`, the - side in a slot of its own past
// every node's (octree.sides.x + an index octree_fill.comp gives it). Every light
// buffer (radiance, estimate, direct, mean, bounces) has both. One light for both
// sides would let a thin wall carry the light of one side to the other. The normal
// word's w codes the axis, (axis + 1) / 4 (0 for an oriented leaf and for inner
// nodes); its other 24 bits, where an oriented leaf keeps its normal, hold the index.
int leafAxis(uint normalWord) { return int(round(unpackSnorm4x8(normalWord).w * 4.0)) - 1; }
// A leaf's (or inner node's) normal: 0 for a two-sided leaf, whose faces cancel.
vec3 leafNormal(uint normalWord) {
  return leafAxis(normalWord) >= 0 ? vec3(0.0) : unpackSnorm4x8(normalWord).xyz;
}
uint backSlot(uint normalWord) { return octree.sides.x + (normalWord & 0xFFFFFFu); }
// The slot of a node's light as seen from unit direction `facing` (from the surface
// towards whoever looks: -dir for a ray along dir, the normal at a triangle hit).
uint lightSlot(uint node, uint normalWord, vec3 facing) {
  int axis = leafAxis(normalWord);
  return axis >= 0 && facing[axis] < 0.0 ? backSlot(normalWord) : node;
}

// A ray that meets an oriented leaf from behind (its normal, where the sides do not
// cancel, points along the ray) sees the inside of a closed surface, which no light
// reaches: the voxel occludes but shows no light. Without this, a ray that starts
// just inside a neighbour's voxel shell, at a contact, gathers the lit outside of
// that neighbour's far side through its inside (a bright ring under a sphere).
// `normalWord` is the leaf's packed snorm normal (the material buffer's .y).
bool seenFromBehind(uint normalWord, vec3 dir) {
  vec3 n = leafNormal(normalWord);
  float len2 = dot(n, n);
  return len2 > 0.25 && dot(n, dir) > 0.25 * sqrt(len2);
}

// Invocation index of a 1D job spread over a 2D dispatch (more than 65535 groups).
uint octreeInvocation() {
  return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * kOctreeGroupSize +
         gl_LocalInvocationID.x;
}

// The unit normal of side `back` of a two-sided leaf's axis.
vec3 sideNormal(int axis, bool back) {
  vec3 n = vec3(0.0);
  n[axis] = back ? -1.0 : 1.0;
  return n;
}

int octreeDepth() { return int(octree.info.x); }
int octreeRootSize() { return int(octree.info.y); }
float octreeVoxelSize() { return octree.origin.w; }
// The point a leaf's rays leave from, and its light is taken at, where no surface is
// found under its centre (octree_inject.comp, octree_bounce.comp): leafRayOffset
// voxels along n (world units).
vec3 leafOffPoint(vec3 centre, vec3 n) {
  return centre + n * (leafRayOffset(n) * octreeVoxelSize());
}

vec3 octreeToGrid(vec3 p) { return (p - octree.origin.xyz) / octree.origin.w; }
vec3 octreeToWorld(vec3 g) { return octree.origin.xyz + g * octree.origin.w; }

// Shared-exponent RGB (9-bit mantissas, 5-bit exponent), the layout of
// GL_RGB9_E5 (EXT_texture_shared_exponent): 4 bytes, relative precision 2^-9 of the
// largest channel, range [0, 65408]. Negative and NaN channels become 0, Inf the
// largest value; a NaN or Inf is counted (nonfinite.glsl).
const float kRgb9e5Max = 65408.0;
uint packRgb9e5(vec3 c) {
  if (any(notFinite(c))) atomicAdd(nonfiniteCount, 1u);
  c = clamp(mix(c, vec3(0.0), isnan(c)), vec3(0.0), vec3(kRgb9e5Max));
  float m = max(c.r, max(c.g, c.b));
  int e = max(-16, int(floor(log2(max(m, 1e-30))))) + 16;
  float scale = exp2(float(e - 24));
  if (floor(m / scale + 0.5) >= 512.0) {
    scale *= 2.0;
    ++e;
  }
  uvec3 q = uvec3(floor(c / scale + 0.5));
  return q.r | (q.g << 9) | (q.b << 18) | (uint(e) << 27);
}
vec3 unpackRgb9e5(uint v) {
  float scale = exp2(float(int(v >> 27) - 24));
  return vec3(float(v & 511u), float((v >> 9) & 511u), float((v >> 18) & 511u)) * scale;
}

uint childIndex(ivec3 v, int depth, int level) {
  int shift = depth - 1 - level;
  return uint((v.x >> shift) & 1) | (uint((v.y >> shift) & 1) << 1) |
         (uint((v.z >> shift) & 1) << 2);
}

// A ray in world space from p along unit direction dir, skipping the first tStart
// voxels and ending after tEnd voxels.
MarchRay octreeWorldRay(vec3 p, vec3 dir, float tEnd) {
  // Components too small to invert are treated as parallel to the axis.
  vec3 d = mix(dir, vec3(0.0), lessThan(abs(dir), vec3(1e-20)));
  return marchRay(octreeToGrid(p), d, vec3(1.0) / d, tEnd);
}

// First occupied leaf along the ray from tStart (voxels) on.
MarchHit octreeTrace(MarchRay r, float tStart, int maxSteps) {
  MarchState s;
  if (!marchBegin(r, tStart, octreeRootSize(), s)) {
    MarchHit h;
    h.hit = false;
    h.voxel = ivec3(0);
    h.node = 0u;
    h.t = r.tEnd;
    h.steps = 0;
    return h;
  }
  return octreeFirstHit(r, octreeDepth(), s, maxSteps);
}

#endif  // VOXGI_OCTREE_GLSL
