// The voxels' light at the hit of a ray on the exact triangles (rtgi's indirect rays
// from the pixels and from reflected hits). Include after rtgi_bvh.glsl, with the
// octree's radiance[] and material[] declared; with RTGI_VOXEL_AT_ONLY, voxelAt alone
// (material[] only: the octree's bounce pass, which reads another light buffer).
#ifndef VOXGI_RTGI_VOXEL_LIGHT_GLSL
#define VOXGI_RTGI_VOXEL_LIGHT_GLSL

// The leaf whose light stands for the point where the ray from o along unit dir
// meets a triangle, t world units away: the first leaf about that point that faces
// the ray, marched from half a voxel before the point to one past it. A leaf seen
// from behind there belongs to another surface at a contact (the floor's own voxels
// under a sphere), or to the back of the one hit; it is passed over. None (-1): a
// surface without voxels, or the inside of a closed one.
int voxelAt(vec3 o, vec3 dir, float t) {
  float tv = t / octreeVoxelSize();
  MarchRay r = octreeWorldRay(o, dir, tv + 1.0);
  float start = max(tv - 0.5, 0.0);
  for (int k = 0; k < 3; ++k) {
    MarchHit h = octreeTrace(r, start, 8);
    if (!h.hit) break;
    if (!seenFromBehind(material[h.node].y, dir)) return int(h.node);
    // On past the leaf: where the ray leaves its cell.
    vec3 far = vec3(h.voxel) + max(vec3(r.stepDir), vec3(0.0));
    vec3 tf = mix(vec3(kMarchInf), (far - r.o) * r.invD, notEqual(r.stepDir, ivec3(0)));
    start = min(min(tf.x, tf.y), tf.z) + 1e-4;
  }
  return -1;
}

#ifndef RTGI_VOXEL_AT_ONLY
// The voxels' light at that point (voxelAt); none where no leaf stands for it.
vec3 voxelLightAt(vec3 o, vec3 dir, float t) {
  int node = voxelAt(o, dir, t);
  return node >= 0 ? unpackRgb9e5(radiance[lightSlot(uint(node), material[node].y, -dir)])
                   : vec3(0.0);
}

// The voxels' light arriving at o from unit direction dir: where the ray meets a
// triangle, none where it leaves the scene.
vec3 voxelLightAlong(vec3 o, vec3 dir) {
  float t;
  uint tri;
  vec2 bc;
  loopBudget = kPtLoopBudget;
  return trace(o, dir, kInf, false, t, tri, bc) ? voxelLightAt(o, dir, t) : vec3(0.0);
}
#endif  // RTGI_VOXEL_AT_ONLY

#endif  // VOXGI_RTGI_VOXEL_LIGHT_GLSL
