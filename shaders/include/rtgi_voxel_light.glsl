// The voxels' light at the hit of a ray on the exact triangles (rtgi's indirect rays
// from the pixels and from reflected hits). Include after rtgi_bvh.glsl, with the
// octree's radiance[] and material[] declared; with RTGI_VOXEL_AT_ONLY, voxelAt and
// leafToHit alone (material[] only: the octree's bounce pass, which reads another
// light buffer).
#ifndef VOXGI_RTGI_VOXEL_LIGHT_GLSL
#define VOXGI_RTGI_VOXEL_LIGHT_GLSL

// The leaf whose light stands for the point where the ray from o along unit dir
// meets a triangle, t world units away: the first leaf about that point that faces
// the ray, marched from half a voxel before the point to one past it. A leaf seen
// from behind there belongs to another surface at a contact (the floor's own voxels
// under a sphere), or to the back of the one hit; it is passed over. None (-1): a
// surface without voxels, or the inside of a closed one. `cell`: its voxel.
int voxelAtCell(vec3 o, vec3 dir, float t, out ivec3 cell) {
  cell = ivec3(0);
  float tv = t / octreeVoxelSize();
  MarchRay r = octreeWorldRay(o, dir, tv + 1.0);
  float start = max(tv - 0.5, 0.0);
  for (int k = 0; k < 3; ++k) {
    MarchHit h = octreeTrace(r, start, 8);
    if (!h.hit) break;
    cell = h.voxel;
    if (!seenFromBehind(material[h.node].y, dir)) return int(h.node);
    // On past the leaf: where the ray leaves its cell.
    vec3 far = vec3(h.voxel) + max(vec3(r.stepDir), vec3(0.0));
    vec3 tf = mix(vec3(kMarchInf), (far - r.o) * r.invD, notEqual(r.stepDir, ivec3(0)));
    start = min(min(tf.x, tf.y), tf.z) + 1e-4;
  }
  return -1;
}

int voxelAt(vec3 o, vec3 dir, float t) {
  ivec3 cell;
  return voxelAtCell(o, dir, t, cell);
}

// A leaf's light is its albedo, the mean base colour of the surfaces in its voxel,
// times the light arriving there. Where a ray meets one of them, that light is
// reflected by the base colour `base` of the triangle met: the factor that turns the
// one into the other, per channel (0 where the leaf reflects nothing, so keeps no
// trace of what arrives; at most kMaxLeafToHit). A voxel holds surfaces a ray may
// not see: the day hall's black skylight panel lies 2 cm below the plaster that
// seals it, and its voxels' albedo, 0.35, sent the floor's light back down as
// the panel never does (the voxels' bounces came out 4.6% bright).
const float kMaxLeafToHit = 8.0;
vec3 leafToHit(uint node, vec3 base) {
  vec3 a = unpackUnorm4x8(material[node].x).rgb;
  vec3 k = min(base / max(a, vec3(1e-6)), vec3(kMaxLeafToHit));
  return mix(vec3(0.0), k, greaterThan(a, vec3(0.5 / 255.0)));
}

#ifndef RTGI_VOXEL_AT_ONLY
// The voxels' light arriving at o from unit direction dir: where the ray meets a
// triangle, none where it leaves the scene.
vec3 voxelLightAlong(vec3 o, vec3 dir) {
  float t;
  uint tri;
  vec2 bc;
  loopBudget = kPtLoopBudget;
  if (!trace(o, dir, kInf, false, t, tri, bc)) return vec3(0.0);
  int node = voxelAt(o, dir, t);
  return node >= 0 ? leafToHit(uint(node), hitBaseColor(tri, bc)) *
                         unpackRgb9e5(radiance[lightSlot(uint(node), material[node].y, -dir)])
                   : vec3(0.0);
}
#endif  // RTGI_VOXEL_AT_ONLY

#endif  // VOXGI_RTGI_VOXEL_LIGHT_GLSL
