// The surface a ray meets on the exact triangles, read as the path tracer reads it:
// the material with its textures, vertex colours and normal map at the hit
// (RTGI_BVH_TEXTURES, _COLORS, _TANGENTS), the normals turned towards the ray. Used
// where rtgi shades a hit with exact direct light: the specular stage's reflected
// rays and the indirect stage's cosine rays. Include after rtgi_bvh.glsl and
// lighting.glsl.
#ifndef VOXGI_RTGI_HIT_GLSL
#define VOXGI_RTGI_HIT_GLSL

struct TriangleHit {
  float t;          // along the ray, world units
  Surface s;        // s.v = -dir; s.n the shading normal (mapped), towards the ray
  vec3 ng;          // the triangle's normal, towards the ray
  vec3 below;       // ng where a normal map tilts s.n, else 0 (the leak rule)
  vec3 emission;    // what the hit emits towards the ray (0 under VOXGI_NO_EMISSION)
  float roughness;  // kMirrorRoughness and below: a mirror
  vec3 base;        // base colour (the voxels' albedo: what they reflect as Lambert)
  float metallic;
  uint tri;  // the triangle, in BVH order (loadTriangle)
};

// Traces the ray from o along unit dir; false where it leaves the scene. Set
// loopBudget first.
bool traceSurface(vec3 o, vec3 dir, out TriangleHit h) {
  uint tri;
  vec2 bc;
  if (!trace(o, dir, kInf, false, h.t, tri, bc)) return false;
  h.tri = tri;
  GpuPtTriangle T = loadTriangle(tri);
  GpuMaterial m = hitMaterial(tri, bc);
  vec3 p = T.v0.xyz + bc.x * T.e1.xyz + bc.y * T.e2.xyz;
  vec3 ng = normalize(cross(T.e1.xyz, T.e2.xyz));
  bool front = dot(ng, dir) < 0.0;
  h.emission = vec3(0.0);
#ifndef VOXGI_NO_EMISSION
  if (front || (m.flags & kMaterialDoubleSided) != 0u) h.emission = m.emission;
#endif
  vec3 ns = normalize(triangleNormal(tri, bc));
  if (!front) {
    ng = -ng;
    ns = -ns;
  }
  if (dot(ns, -dir) <= 0.0 || !(dot(ns, ns) > 0.5)) ns = ng;
  vec3 ngFlat = ns;
#ifdef RTGI_BVH_TANGENTS
  if ((m.flags & kMaterialHasNormalTexture) != 0u) {
    // The normal map and the back-facing rule, as the path tracer does.
    vec4 tangent = triangleTangent(tri, bc);
    if (!front) tangent.w = -tangent.w;
    vec2 uv = triangleUv(tri, bc);
    vec2 uv2 = (m.flags & kMaterialNormalUv2) != 0u ? triangleUv2(tri, bc) : uv;
    ns = bendShadingNormal(mappedNormal(m, ns, tangent, uv, uv2), -dir);
  }
#endif
  float metallic = m.metallic;
  h.metallic = metallic;
  h.roughness = clamp(m.roughness, 0.0, 1.0);
  vec3 base = m.baseColor.rgb;
  h.base = base;
  h.s.p = p;
  h.s.n = ns;
  h.s.v = -dir;
  h.s.diffuse = base * (1.0 - metallic);
  h.s.f0 = metallicF0(base, metallic);
  h.s.alpha = h.roughness * h.roughness;
  h.s.specular = isLambertian(metallic, h.roughness) ? 0.0 : 1.0;
  h.ng = ng;
  h.below = ns != ngFlat ? ng : vec3(0.0);
  return true;
}

#endif  // VOXGI_RTGI_HIT_GLSL
