// Voxelization: grid-space set-up of one triangle, shared by the vertex and
// geometry stages of the raster and by the compute path for small triangles.
// Which path takes a triangle is decided once, by the compute path, which passes
// the others on to the raster. Grid positions are `precise` (no fused or reordered
// arithmetic), so both paths place a vertex at the same point and test the same
// samples. The includer declares the VoxelBlock uniform block (`voxel`).
//
// Projection along the dominant axis (Crassin & Green, "Octree-Based Sparse
// Voxelization Using the GPU Hardware Rasterizer", OpenGL Insights ch. 22): the
// axis the normal is most aligned with maximises the rasterized area. Grid space
// is swizzled so that axis becomes z; pixels are voxels, (u, v) = swizzled (x, y).

// Scene space -> grid space (voxel units, [0, N]).
vec3 voxelGridPosition(vec3 scenePosition) {
  precise vec3 g = (scenePosition - voxel.gridOrigin.xyz) / voxel.gridOrigin.w;
  return g;
}

vec3 voxelSwizzle(vec3 p, int axis) { return axis == 0 ? p.yzx : (axis == 1 ? p.zxy : p); }

// The projection axis (0: x, 1: y, 2: z) and the grid-space normal (not unit);
// -1 for a triangle of no area in grid space.
int voxelProjectionAxis(vec3 g0, vec3 g1, vec3 g2, out vec3 n) {
  precise vec3 e1 = g1 - g0;
  precise vec3 e2 = g2 - g0;
  precise vec3 c = cross(e1, e2);
  n = c;
  vec3 a = abs(c);
  int axis = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
  return a[axis] > 0.0 ? axis : -1;
}

// Small triangles, whose projection reaches at most kSmallTriangleSpan pixel
// columns and rows, go to the compute path (voxelize_small.comp): on a software
// rasterizer each triangle costs its set-up and binning however few pixels it
// covers, and a compute invocation tests a handful of samples for much less.
bool voxelIsSmallTriangle(vec3 s0, vec3 s1, vec3 s2) {
  vec2 lo = floor(min(s0.xy, min(s1.xy, s2.xy)));
  vec2 hi = floor(max(s0.xy, max(s1.xy, s2.xy)));
  return hi.x - lo.x < float(kSmallTriangleSpan) && hi.y - lo.y < float(kSmallTriangleSpan);
}

// The triangle's plane over the projection, z = plane.x + plane.y u + plane.z v
// (sn: the swizzled normal, sn.z != 0), and its z range.
vec4 voxelPlane(vec3 s0, vec3 sn) {
  return vec4(dot(sn, s0) / sn.z, -sn.x / sn.z, -sn.y / sn.z, 0.0);
}
vec2 voxelDepthRange(vec3 s0, vec3 s1, vec3 s2) {
  return vec2(min(s0.z, min(s1.z, s2.z)), max(s0.z, max(s1.z, s2.z)));
}
