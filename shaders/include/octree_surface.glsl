// The surface a leaf stands for, found on the scene's exact triangles (OCTREE_BVH):
// where the leaves' direct light is taken (octree_inject.comp) and their bounce rays
// start (octree_bounce.comp). Include after octree.glsl and rtgi_bvh.glsl.
#ifndef VOXGI_OCTREE_SURFACE_GLSL
#define VOXGI_OCTREE_SURFACE_GLSL

layout(std430, binding = kOctreeSurfaceBinding) buffer Surfaces { uint surfaces[]; };

// Where the leaf's own surface lies, for its light slot `slot`: on the first
// triangle that a ray from a voxel above the centre, down along -n, meets within two
// voxels, that ray's point on the triangle's plane, the normal turned to n's side;
// false where none does. The triangle is looked for once per slot and kept (the
// bounce passes and every refinement ask again: one ray less per leaf and pass).
bool surfaceBelow(vec3 centre, vec3 n, uint slot, out vec3 p) {
  float h = octreeVoxelSize();
  vec3 o = centre + n * h;
  uint cached = surfaces[slot];
  if (cached == kOctreeNoSurface) return false;
  uint tri = cached - 1u;
  if (cached == 0u) {
    float t;
    vec2 bc;
    loopBudget = kPtLoopBudget;
    bool hit = trace(o, -n, 2.0 * h, false, t, tri, bc);
    surfaces[slot] = hit ? tri + 1u : kOctreeNoSurface;
    if (!hit) return false;
  }
  GpuPtTriangle T = loadTriangle(tri);
  vec3 ng = normalize(cross(T.e1.xyz, T.e2.xyz));
  if (dot(ng, n) < 0.0) ng = -ng;
  // The hit's distance along -n, from the plane (the same in every pass).
  float t = dot(o - T.v0.xyz, ng) / max(dot(n, ng), 1e-6);
  p = o - n * t + ng * bvhEpsilon();
  return true;
}

#endif  // VOXGI_OCTREE_SURFACE_GLSL
