#version 450 core
// rtgi stage "specular": light along the reflection. Mirrors (roughness below
// kMirrorRoughness) trace the reflected ray and see the light the voxel it hits
// reflects, or an emitter's exact geometry where the ray meets one first (a light
// the size of its voxels would look too big); glossy surfaces trace one ray per frame towards a GGX micro-normal
// drawn from the visible normals (Heitz 2018) and see reflected light only (their
// highlight from the lights comes from the shadows stage). Weighted by Schlick's
// Fresnel. Dielectrics rougher than kGlossyRoughness are skipped.
//
// RTGI_BVH (the effect plan has the specular effect and the Renderer built a BVH):
// the reflected ray finds its hit on the exact triangles (bvh_trace.glsl) instead,
// passes on through up to kMaxMirrorChain further mirrors, and is shaded there with
// exact direct light, the rtgi_direct.comp estimators with shadow rays through the
// BVH (RTGI_LIGHTS, RTGI_EMITTERS_EXACT / _SAMPLED as there), plus the voxels' light
// along one cosine ray from the hit (the indirect stage's estimate), when the plan
// has indirect light: voxels serve only as the light cache behind the hit. A mirror
// sees an emitter it hits; a glossy surface does not (its highlight comes from the
// shadows stage). RTGI_BVH_TEXTURES (a textured BVH): the material's textures at the hit
// (base colour, metallic-roughness, emission), sampled as the path tracer samples
// them (bilinear, no mipmaps). RTGI_BVH_COLORS: the vertex colours at the hit.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "octree_light.glsl"
#define RTGI_PIXEL_LIST
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiTraceGroup) in;

layout(std430, binding = kOctreeRadianceBinding) readonly buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeMaterialBinding) readonly buffer Material { uvec2 material[]; };
layout(binding = kSpecularImage, rgba16f) uniform writeonly image2D specularOut;

#ifdef RTGI_BVH
#include "pathtrace_shared.h"
layout(std430, binding = kMaterialBinding) readonly buffer Materials { GpuMaterial materials[]; };
layout(binding = kRtgiBvhNodeUnit) uniform usamplerBuffer nodeTexels;
layout(binding = kRtgiBvhTriangleUnit) uniform usamplerBuffer triangleTexels;
layout(std430, binding = kRtgiBvhShadingBinding) readonly buffer Shading { GpuPtShading shading[]; };
uint loopBudget;  // see kPtLoopBudget
const float kInf = 1.0 / 0.0;

#ifdef RTGI_BVH_TEXTURES
layout(std430, binding = kRtgiBvhTextureBinding) readonly buffer Textures { uvec4 textures[]; };
layout(binding = kRtgiBvhUvUnit) uniform usamplerBuffer uvTexels;
layout(binding = kRtgiBvhTexelUnit) uniform usamplerBuffer textureTexels;
#define VOXGI_BVH_UVS
#endif
#ifdef RTGI_BVH_COLORS
#define VOXGI_BVH_COLORS
#define VOXGI_BVH_COLOR_BINDING kRtgiBvhColorBinding
#endif
#ifdef RTGI_BVH_TANGENTS
#define VOXGI_BVH_TANGENTS
#define VOXGI_BVH_TANGENT_BINDING kRtgiBvhTangentBinding
#endif
#include "bvh_trace.glsl"

#ifdef RTGI_BVH_TEXTURES
// The path tracer's texture reads (texture_shared.h).
#define VOXGI_TABLES_PARAM
#define VOXGI_TABLES_ARG
#define VOXGI_TEXEL(i) texelFetch(textureTexels, int(i)).x
#define VOXGI_TEXTURE(i) textures[i]
#include "texture_shared.h"
#endif

// Ray offset off a triangle: a thousandth of a voxel, scaled with the scene.
float bvhEpsilon() { return 1e-3 * octreeVoxelSize(); }

// 1 if nothing but emitters lies between p and the point `dist` away along unit l:
// the emitter a shadow ray aims at does not shadow itself.
float bvhVisible(vec3 p, vec3 l, float dist) {
#ifdef VOXGI_NO_SHADOWS
  return 1.0;
#else
  float t;
  uint tri;
  vec2 bc;
  float tMax = min(dist, 3.0e38) * (1.0 - 1e-4);
  if (!trace(p, l, tMax, false, t, tri, bc)) return 1.0;
  GpuMaterial m = materials[floatBitsToUint(shading[tri].n0.w)];
#ifdef RTGI_BVH_TEXTURES
  // Where an emissive texture is black, the surface is no emitter: it shadows.
  if ((m.flags & kMaterialHasEmissiveTexture) != 0u) m = texturedMaterial(m, triangleUv(tri, bc));
#endif
  return m.emission.rgb != vec3(0.0) ? 1.0 : 0.0;
#endif
}

// Exact direct light reflected at s towards s.v, shadow rays from o (rtgi_direct.comp's
// estimators, visibility through the BVH).
vec3 directLight(Surface s, vec3 o) {
  vec3 result = vec3(0.0);
#ifdef RTGI_LIGHTS
  int lightCount = int(rtgi.counts.x);
  for (int k = 0; k < lightCount; ++k) {
    vec3 c = punctualLight(lights[k], s);
    if (all(equal(c, vec3(0.0)))) continue;
    vec3 l;
    float dist;
    punctualDirection(lights[k], s.p, l, dist);
    result += c * bvhVisible(o, l, dist);
  }
#endif
#ifndef VOXGI_NO_EMISSION
  int emitterCount = int(rtgi.counts.y);
#if defined(RTGI_EMITTERS_EXACT)
  {
    vec3 sum = vec3(0.0);
    float total = 0.0;
    float u = rand01();
    int pick = -1;
    for (int k = 0; k < emitterCount; ++k) {
      vec3 c = areaLight(emitters[k], s);
      float w = dot(c, vec3(0.2126, 0.7152, 0.0722));
      sum += c;
      if (!(w > 0.0)) continue;
      total += w;
      float q = w / total;
      if (u < q) {
        pick = k;
        u = u / q;
      } else {
        u = (u - q) / (1.0 - q);
      }
    }
    if (pick >= 0) {
      vec3 q = emitterPoint(emitters[pick], vec2(rand01(), rand01()));
      vec3 d = q - o;
      float dist = length(d);
      result += sum * (dist > 0.0 ? bvhVisible(o, d / dist, dist) : 1.0);
    }
  }
#elif defined(RTGI_EMITTERS_SAMPLED)
  if (emitterCount > 0) {
    float pmf;
    GpuEmitter e = emitters[pickEmitter(rand01(), emitterCount, pmf)];
    vec3 c = areaLight(e, s);
    if (pmf > 0.0 && any(greaterThan(c, vec3(0.0)))) {
      vec3 q = emitterPoint(e, vec2(rand01(), rand01()));
      vec3 d = q - o;
      float dist = length(d);
      result += c * (dist > 0.0 ? bvhVisible(o, d / dist, dist) : 1.0) / pmf;
    }
  }
#endif
#endif
  return result;
}

// Radiance arriving at o from unit direction dir: the nearest triangle's (after up to
// kMaxMirrorChain mirrors) direct light, its voxel indirect light and, when
// `seeEmitters`, its emission.
vec3 reflectedRadiance(vec3 o, vec3 dir, bool seeEmitters) {
  loopBudget = kPtLoopBudget;
  float eps = bvhEpsilon();
  vec3 throughput = vec3(1.0);
  vec3 result = vec3(0.0);
  for (int bounce = 0; bounce <= kMaxMirrorChain; ++bounce) {
    float t;
    uint tri;
    vec2 bc;
    if (!trace(o, dir, kInf, false, t, tri, bc)) break;
    GpuPtTriangle T = loadTriangle(tri);
    GpuPtShading S = shading[tri];
    GpuMaterial m = materials[floatBitsToUint(S.n0.w)];
#ifdef RTGI_BVH_TEXTURES
    if ((m.flags & (kMaterialHasTexture | kMaterialHasEmissiveTexture |
                    kMaterialHasMetallicRoughnessTexture)) != 0u)
      m = texturedMaterial(m, triangleUv(tri, bc));
#endif
#ifdef RTGI_BVH_COLORS
    m.baseColor *= triangleColor(tri, bc);
#endif
    vec3 p = T.v0.xyz + bc.x * T.e1.xyz + bc.y * T.e2.xyz;
    vec3 ng = normalize(cross(T.e1.xyz, T.e2.xyz));
    bool front = dot(ng, dir) < 0.0;
#ifndef VOXGI_NO_EMISSION
    if (seeEmitters && (front || (m.flags & kMaterialDoubleSided) != 0u))
      result += throughput * m.emission.rgb;
#endif
    vec3 ns = normalize((1.0 - bc.x - bc.y) * S.n0.xyz + bc.x * S.n1.xyz + bc.y * S.n2.xyz);
    if (!front) {
      ng = -ng;
      ns = -ns;
    }
    if (dot(ns, -dir) <= 0.0 || !(dot(ns, ns) > 0.5)) ns = ng;
#ifdef RTGI_BVH_TANGENTS
    if ((m.flags & kMaterialHasNormalTexture) != 0u) {
      // The normal map and the back-facing rule, as the path tracer does.
      vec4 tangent = triangleTangent(tri, bc);
      if (!front) tangent.w = -tangent.w;
      ns = bendShadingNormal(mappedNormal(m, ns, tangent, triangleUv(tri, bc)), -dir);
    }
#endif
    float metallic = m.params.x;
    float roughness = clamp(m.params.y, 0.0, 1.0);
    vec3 base = m.baseColor.rgb;
    vec3 f0 = mix(vec3(0.04), base, metallic);
    if (roughness < kMirrorRoughness) {
      // A mirror: on along the reflection, weighted as the first (Schlick).
      if (bounce == kMaxMirrorChain) break;
      throughput *= f0 + (1.0 - f0) * pow(1.0 - clamp(dot(ns, -dir), 0.0, 1.0), 5.0);
      dir = reflect(dir, ns);
      if (dot(dir, ng) <= 0.0) break;
      o = p + ng * eps;
      continue;
    }
    Surface s;
    s.p = p;
    s.n = ns;
    s.v = -dir;
    s.diffuse = base * (1.0 - metallic);
    s.f0 = f0;
    s.alpha = roughness * roughness;
    s.specular = isLambertian(metallic, roughness) ? 0.0 : 1.0;
    result += throughput * directLight(s, p + ng * eps);
    if ((rtgi.counts.z & kRtgiHasIndirect) != 0u && any(greaterThan(s.diffuse, vec3(0.0)))) {
      vec3 d = cosineSample(ns, vec2(rand01(), rand01()));
      MarchHit h = octreeTrace(octreeWorldRay(rayOrigin(s), d, 3.0e38), 0.0, kRaySteps);
      if (h.hit && !seenFromBehind(material[h.node].y, d))
        result += throughput * s.diffuse * unpackRgb9e5(radiance[h.node]);
    }
    break;
  }
  return result;
}
#endif

void main() {
  ivec2 px;
  if (!tracePixel(px)) return;
  Pixel p = loadPixel(px);
  vec3 result = vec3(0.0);
  bool mirror = p.roughness < kMirrorRoughness;
  if (p.covered && (mirror || p.metallic > 0.5 || p.roughness < kGlossyRoughness)) {
    seedPixel(px, 3u);
    Surface s = p.s;
    vec3 dir;
    vec3 h = s.n;
    if (mirror) {
      dir = reflect(-s.v, s.n);
    } else {
      vec3 t, bt;
      basis(s.n, t, bt);
      vec3 ve = vec3(dot(s.v, t), dot(s.v, bt), dot(s.v, s.n));
      vec3 m = sampleVndf(ve, max(s.alpha, 1e-3), vec2(rand01(), rand01()));
      h = normalize(t * m.x + bt * m.y + s.n * m.z);
      dir = reflect(-s.v, h);
    }
    if (dot(dir, s.n) > 0.0) {
      vec3 f = s.f0 + (1.0 - s.f0) * pow(1.0 - clamp(dot(s.v, h), 0.0, 1.0), 5.0);
#ifdef RTGI_BVH
      result = f * reflectedRadiance(s.p + s.n * bvhEpsilon(), dir, mirror);
#else
      vec3 o = rayOrigin(s);
      MarchHit hit = octreeTrace(octreeWorldRay(o, dir, 3.0e38), 0.0, kRaySteps);
      vec3 l = hit.hit && !seenFromBehind(material[hit.node].y, dir)
                   ? unpackRgb9e5(radiance[hit.node])
                   : vec3(0.0);
      if (mirror) {
        // Lights seen in a mirror: the exact emitters, unless a voxel closer than
        // the emitter's own voxels (kSurfaceOffsetVoxels in front) hides them.
        float tVoxel = hit.hit ? (hit.t + 2.0 * kSurfaceOffsetVoxels) * octreeVoxelSize() : 3.0e38;
        vec3 e = emitterAlongRay(o, dir, tVoxel, int(rtgi.counts.y));
        if (any(greaterThan(e, vec3(0.0)))) l = e;
      }
      result = f * l;
#endif
    }
  }
  imageStore(specularOut, px, vec4(result, 1.0));
}
