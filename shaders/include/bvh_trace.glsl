// BVH traversal over the scene's exact triangles (src/render/gpu_bvh.h), shared by
// the path tracer (pathtrace.comp) and rtgi's reflections (rtgi_specular.comp).
// Include after pathtrace_shared.h. The including shader declares what this reads:
//   usamplerBuffer nodeTexels, triangleTexels   the BVH (RGBA32UI buffer textures)
//   uint loopBudget   loop iterations the invocation may still run (kPtLoopBudget);
//                     every node visited spends one
//   const float kInf = 1.0 / 0.0
#ifndef VOXGI_BVH_TRACE_GLSL
#define VOXGI_BVH_TRACE_GLSL

// Node and triangle i from their buffer textures (see pathtrace_shared.h).
GpuBvhNode loadNode(uint i) {
  int b = int(i) * 4;
  GpuBvhNode n;
  n.leftMin = uintBitsToFloat(texelFetch(nodeTexels, b));
  n.leftMax = uintBitsToFloat(texelFetch(nodeTexels, b + 1));
  n.rightMin = uintBitsToFloat(texelFetch(nodeTexels, b + 2));
  n.rightMax = uintBitsToFloat(texelFetch(nodeTexels, b + 3));
  return n;
}
GpuPtTriangle loadTriangle(uint i) {
  int b = int(i) * 3;
  GpuPtTriangle t;
  t.v0 = uintBitsToFloat(texelFetch(triangleTexels, b));
  t.e1 = uintBitsToFloat(texelFetch(triangleTexels, b + 1));
  t.e2 = uintBitsToFloat(texelFetch(triangleTexels, b + 2));
  return t;
}

#ifdef VOXGI_BVH_UVS
// Texture coordinates at barycentrics bc of triangle tri, from the corner UVs in
// `usamplerBuffer uvTexels` (two RGBA32UI texels a triangle, BVH order), which the
// including shader declares when it defines VOXGI_BVH_UVS.
vec2 triangleUv(uint tri, vec2 bc) {
  vec4 a = uintBitsToFloat(texelFetch(uvTexels, int(tri) * 2));
  vec2 c = uintBitsToFloat(texelFetch(uvTexels, int(tri) * 2 + 1).xy);
  return (1.0 - bc.x - bc.y) * a.xy + bc.x * a.zw + bc.y * c;
}
#endif

#ifdef VOXGI_BVH_COLORS
// The vertex colour (COLOR_0) at barycentrics bc of triangle tri, from its corners'
// colours (three a triangle, BVH order; scene side: render/gpu_bvh.h), an SSBO at the
// binding VOXGI_BVH_COLOR_BINDING, which the including shader defines.
layout(std430, binding = VOXGI_BVH_COLOR_BINDING) readonly buffer BvhColors { vec4 bvhCornerColors[]; };
vec4 triangleColor(uint tri, vec2 bc) {
  uint b = tri * 3u;
  return (1.0 - bc.x - bc.y) * bvhCornerColors[b] + bc.x * bvhCornerColors[b + 1u] +
         bc.y * bvhCornerColors[b + 2u];
}
#endif

#ifdef VOXGI_BVH_TANGENTS
// The tangent (xyz, w handedness) at barycentrics bc of triangle tri, from its
// corners' tangents (three a triangle, BVH order; scene side: render/gpu_bvh.h), an
// SSBO at the binding VOXGI_BVH_TANGENT_BINDING, which the including shader defines.
layout(std430, binding = VOXGI_BVH_TANGENT_BINDING) readonly buffer BvhTangents { vec4 bvhCornerTangents[]; };
vec4 triangleTangent(uint tri, vec2 bc) {
  uint b = tri * 3u;
  return (1.0 - bc.x - bc.y) * bvhCornerTangents[b] + bc.x * bvhCornerTangents[b + 1u] +
         bc.y * bvhCornerTangents[b + 2u];
}
#endif

#ifdef VOXGI_BVH_ALPHA
// With VOXGI_BVH_ALPHA, a candidate hit counts only where this returns true (the
// including shader defines it: alpha masks, texture_shared.h's alphaStops).
bool bvhHitStops(uint tri, vec2 bc);
#endif

// --- ray casting --------------------------------------------------------------------
// Slab test against one box; the entry distance, or +inf on a miss.
float hitBox(vec3 lo, vec3 hi, vec3 o, vec3 inv, float tMax) {
  vec3 t0 = (lo - o) * inv;
  vec3 t1 = (hi - o) * inv;
  vec3 tn = min(t0, t1);
  vec3 tf = max(t0, t1);
  float enter = max(max(tn.x, tn.y), max(tn.z, 0.0));
  float exit = min(min(tf.x, tf.y), min(tf.z, tMax));
  return enter <= exit ? enter : kInf;
}

// Closest hit (anyHit false) or any hit in (0, tMax). Short-stack traversal of the
// two-children nodes: descend into the nearer child, push the farther one.
bool trace(vec3 o, vec3 d, float tMax, bool anyHit, out float tHit, out uint triHit,
           out vec2 bary) {
  tHit = tMax;
  triHit = 0u;
  bary = vec2(0.0);
  bool found = false;
  vec3 safe = vec3(abs(d.x) > 1e-20 ? d.x : 1e-20, abs(d.y) > 1e-20 ? d.y : 1e-20,
                   abs(d.z) > 1e-20 ? d.z : 1e-20);
  vec3 inv = 1.0 / safe;
  uint stack[kPtStackSize];
  int sp = 0;
  uint node = 0u;
  while (loopBudget > 0u) {
    --loopBudget;
    GpuBvhNode n = loadNode(node);
    float tl = hitBox(n.leftMin.xyz, n.leftMax.xyz, o, inv, tHit);
    float tr = hitBox(n.rightMin.xyz, n.rightMax.xyz, o, inv, tHit);
    uint li = floatBitsToUint(n.leftMin.w), lc = floatBitsToUint(n.leftMax.w);
    uint ri = floatBitsToUint(n.rightMin.w), rc = floatBitsToUint(n.rightMax.w);
    for (int side = 0; side < 2; ++side) {
      uint first = side == 0 ? li : ri;
      uint count = side == 0 ? lc : rc;
      float tb = side == 0 ? tl : tr;
      if (count == 0u || tb == kInf) continue;
      // A fixed trip count: unrolled, so it does not spend the driver's loop budget.
      for (uint j = 0u; j < kPtMaxLeafSize; ++j) {
        if (j >= count) break;
        uint i = first + j;
        // Moeller-Trumbore; NaN (a ray in the triangle's plane) fails every test.
        GpuPtTriangle t = loadTriangle(i);
        vec3 p = cross(d, t.e2.xyz);
        float inv_det = 1.0 / dot(t.e1.xyz, p);
        vec3 s = o - t.v0.xyz;
        float u = dot(s, p) * inv_det;
        vec3 q = cross(s, t.e1.xyz);
        float v = dot(d, q) * inv_det;
        float th = dot(t.e2.xyz, q) * inv_det;
        if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && th > 0.0 && th < tHit
#ifdef VOXGI_BVH_ALPHA
            && bvhHitStops(i, vec2(u, v))
#endif
        ) {
          tHit = th;
          triHit = i;
          bary = vec2(u, v);
          found = true;
        }
      }
      if (anyHit && found) return true;
    }
    bool goL = lc == 0u && li != 0u && tl < tHit;  // node 0 as a child: empty
    bool goR = rc == 0u && ri != 0u && tr < tHit;
    if (goL && goR) {
      bool rFirst = tr < tl;
      node = rFirst ? ri : li;
      stack[sp++] = rFirst ? li : ri;
    } else if (goL) {
      node = li;
    } else if (goR) {
      node = ri;
    } else {
      if (sp == 0) break;
      node = stack[--sp];
    }
  }
  return found;
}

bool occluded(vec3 o, vec3 d, float tMax) {
  float t;
  uint tri;
  vec2 b;
  return trace(o, d, tMax, true, t, tri, b);
}

#endif  // VOXGI_BVH_TRACE_GLSL
