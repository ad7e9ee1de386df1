#version 450 core
// Reference path tracer over the exact triangles (see src/render/pathtrace/pathtrace_pass.h).
// One invocation owns one pixel and adds `samples per pass` paths to its running
// sum (Kahan-compensated), then writes the mean. Unidirectional path tracing with
// next-event estimation and multiple importance sampling (Veach 1997, power
// heuristic), Russian roulette, depths in Mitsuba's convention: the vertex the
// camera ray hits is depth 1; emission seen there is a path of depth 1, light
// gathered there by NEE a path of depth 2.
#include "scene_shared.h"
#include "pathtrace_shared.h"
#include "sampling.glsl"

// Loop iterations this path may still run (see kPtLoopBudget).
uint loopBudget;

layout(local_size_x = kPtGroupX, local_size_y = kPtGroupY) in;

layout(std140, binding = kPtParamsBinding) uniform PtParamsBlock { GpuPtParams params; };
layout(std430, binding = kMaterialBinding) readonly buffer Materials { GpuMaterial materials[]; };
layout(std430, binding = kLightBinding) readonly buffer Lights { GpuLight lights[]; };
layout(binding = kPtNodeTexUnit) uniform usamplerBuffer nodeTexels;
layout(binding = kPtTriangleTexUnit) uniform usamplerBuffer triangleTexels;
layout(binding = kPtVertexTexUnit) uniform samplerBuffer sceneVertexTexels;
layout(std430, binding = kPtIndexBinding) readonly buffer SceneIndices { uint sceneIndices[]; };
layout(std430, binding = kPtEmissiveBinding) readonly buffer Emissive { GpuPtEmissive emissive[]; };
layout(std430, binding = kPtCounterBinding) buffer Counters { uint truncatedPaths; };
#ifndef VOXGI_NO_TEXTURES
layout(std430, binding = kPtTextureBinding) readonly buffer Textures { uvec4 textures[]; };
layout(binding = kPtTexelTexUnit) uniform usamplerBuffer textureTexels;
#endif
layout(binding = kPtSumImage, rgba32f) uniform image2D sumImage;
layout(binding = kPtCompensationImage, rgba32f) uniform image2D compensationImage;
layout(binding = kPtOutputImage, rgba32f) uniform writeonly image2D outImage;

// Materials, light sampling and texture reads, shared with the CPU device.
#define VOXGI_TABLES_PARAM
#define VOXGI_TABLES_ARG
#define VOXGI_EMISSIVE(i) emissive[i]
#ifndef VOXGI_NO_TEXTURES
#define VOXGI_TEXEL(i) texelFetch(textureTexels, int(i)).x
#define VOXGI_TEXTURE(i) textures[i]
#else
#define VOXGI_TEXEL(i) 0u
#endif
#include "pathtrace_shading.h"

const float kInf = 1.0 / 0.0;

#ifndef VOXGI_NO_TEXTURES
#define VOXGI_BVH_UVS
#endif
#ifndef VOXGI_NO_COLORS
#define VOXGI_BVH_COLORS
#define VOXGI_BVH_COLOR_BINDING kPtColorBinding
#endif
#if !defined(VOXGI_NO_NORMALMAPS) && !defined(VOXGI_NO_TEXTURES)
#define VOXGI_PT_NORMALMAPS
#define VOXGI_BVH_TANGENTS
#define VOXGI_BVH_TANGENT_BINDING kPtTangentBinding
#endif
#include "bvh_trace.glsl"

#ifdef VOXGI_BVH_ALPHA
// Alpha masks in traversal: a hit on a masked-out texel does not stop the ray.
bool bvhHitStops(uint tri, vec2 bc) {
  GpuMaterial m = materials[triangleMaterial(tri)];
#ifndef VOXGI_NO_COLORS
  m.baseColor *= triangleColor(tri, bc);
#endif
#ifndef VOXGI_NO_TEXTURES
  uvec4 t = (m.flags & kMaterialHasTexture) != 0u ? textures[m.texture] : uvec4(0u);
  return alphaStops(m, true, t, triangleUv(tri, bc), alphaHash(tri, bc));
#else
  return alphaStops(m, false, uvec4(0u), vec2(0.0), alphaHash(tri, bc));
#endif
}
#endif

// --- lights -------------------------------------------------------------------------
// One emissive triangle by power, one point on it, its shadow ray (MIS with the BSDF).
vec3 sampleEmissive(vec3 p, vec3 n, vec3 wo, Bsdf b, vec3 ng, float eps) {
  float u0 = rand01();
  float u1 = rand01();
  float u2 = rand01();
  EmitterSample ls = sampleEmitter(p, params.tile.w, u0, u1, u2);
  if (!(ls.pdfLight > 0.0)) return vec3(0.0);
  float pdfBsdf;
  vec3 f = evalBsdf(b, n, wo, ls.wi, pdfBsdf);
  if (f == vec3(0.0) || dot(ng, ls.wi) <= 0.0) return vec3(0.0);
  // Aimed at the sampled point from the offset origin (see pathtrace_cpu.cpp).
  vec3 origin = p + ng * eps;
  vec3 toLight = p + ls.wi * ls.dist - origin;
  float shadowDist = length(toLight);
  if (occluded(origin, toLight / shadowDist, shadowDist * (1.0 - 1e-4) - eps)) return vec3(0.0);
  return f * ls.radiance * (powerHeuristic(ls.pdfLight, pdfBsdf) / ls.pdfLight);
}

// Every punctual light, with its shadow ray.
vec3 samplePunctuals(vec3 p, vec3 n, vec3 wo, Bsdf b, vec3 ng, float eps) {
  vec3 sum = vec3(0.0);
  int count = int(params.depth.z);
  for (int i = 0; i < count; ++i) {
    if (loopBudget == 0u) break;
    --loopBudget;
    PunctualSample ls = samplePunctual(lights[i], p);
    if (ls.radiance == vec3(0.0) || dot(ng, ls.wi) <= 0.0) continue;
    float pdf;
    vec3 f = evalBsdf(b, n, wo, ls.wi, pdf);
    if (f == vec3(0.0)) continue;
    if (occluded(p + ng * eps, ls.wi, ls.dist * (1.0 - 1e-4) - eps)) continue;
    sum += f * ls.radiance;
  }
  return sum;
}

// --- one path -----------------------------------------------------------------------
vec3 radiance(vec3 o, vec3 d) {
  vec3 result = vec3(0.0);
  vec3 throughput = vec3(1.0);
  float eps = params.cameraPosition.w;
  int maxDepth = int(params.depth.x);
  int rrDepth = int(params.depth.y);
  bool lightsByNee = params.tile.w > 0u;
  float lastPdf = 0.0;    // solid-angle pdf of the BSDF sample that led here
  bool lastDelta = true;  // camera rays and mirror bounces: emission counts in full
  for (int depth = 1; depth <= maxDepth; ++depth) {
    if (loopBudget == 0u) break;
    --loopBudget;
    float t;
    uint tri;
    vec2 bc;
    if (!trace(o, d, kInf, false, t, tri, bc)) break;  // black background
    GpuPtTriangle T = loadTriangle(tri);
    GpuMaterial m = materials[floatBitsToUint(T.v0.w)];
#ifndef VOXGI_NO_TEXTURES
    vec2 uv = vec2(0.0), uv2 = vec2(0.0);  // texture-coordinate channels 0 and 1
    if ((m.flags & (kMaterialHasTexture | kMaterialHasEmissiveTexture |
                    kMaterialHasMetallicRoughnessTexture | kMaterialHasNormalTexture)) != 0u) {
      uv = triangleUv(tri, bc);
      uv2 = (m.flags & kMaterialAnyUv2) != 0u ? triangleUv2(tri, bc) : uv;
    }
    if ((m.flags & (kMaterialHasTexture | kMaterialHasEmissiveTexture |
                    kMaterialHasMetallicRoughnessTexture)) != 0u)
      m = texturedMaterial(m, uv, uv2);
#endif
#ifndef VOXGI_NO_COLORS
    m.baseColor *= triangleColor(tri, bc);
#endif
    vec3 p = T.v0.xyz + bc.x * T.e1.xyz + bc.y * T.e2.xyz;
    vec3 ng = normalize(cross(T.e1.xyz, T.e2.xyz));
    bool front = dot(ng, d) < 0.0;
    if (m.emission != vec3(0.0) && (front || (m.flags & kMaterialDoubleSided) != 0u)) {
      float w = 1.0;
      if (!lastDelta && lightsByNee && T.e1.w != 0.0)
        w = emissionMisWeight(lastPdf, abs(T.e1.w), t, abs(dot(ng, d)));
      result += throughput * m.emission * w;
    }
    if (depth == maxDepth) break;

    // Shade on the side the ray arrived from.
    vec3 ns = normalize(triangleNormal(tri, bc));
    if (!front) {
      ng = -ng;
      ns = -ns;
    }
    vec3 wo = -d;
    if (dot(ns, wo) <= 0.0 || !(dot(ns, ns) > 0.5)) ns = ng;  // shading normal past the silhouette
#ifdef VOXGI_PT_NORMALMAPS
    if ((m.flags & kMaterialHasNormalTexture) != 0u) {
      // The normal map, then the back-facing rule (normal_map_shared.h); light
      // below ng is rejected below as for any shading normal.
      vec4 tangent = triangleTangent(tri, bc);
      if (!front) tangent.w = -tangent.w;
      ns = bendShadingNormal(mappedNormal(m, ns, tangent, uv, uv2), wo);
    }
#endif
    Bsdf b = makeBsdf(m.baseColor.rgb, m.metallic, m.roughness, dot(ns, wo));
    if (b.kind != kBsdfGgx && b.base == vec3(0.0))
      break;  // black: reflects nothing (the lights of the reference scenes)

    if (b.kind == kBsdfMirror) {
      d = reflect(d, ns);
      if (dot(d, ng) <= 0.0) break;
      throughput *= b.base;
      lastDelta = true;
    } else {
      if (lightsByNee) result += throughput * sampleEmissive(p, ns, wo, b, ng, eps);
      result += throughput * samplePunctuals(p, ns, wo, b, ng, eps);
      vec3 wi;
      if (!sampleBsdf(b, ns, wo, rngState, wi) || dot(wi, ng) <= 0.0) break;
      vec3 f = evalBsdf(b, ns, wo, wi, lastPdf);
      if (!(lastPdf > 0.0)) break;
      throughput *= f / lastPdf;
      d = wi;
      lastDelta = false;
    }
    o = p + ng * eps;
    // Russian roulette from rrDepth on, as Mitsuba does it.
    if (depth >= rrDepth) {
      float q = min(max(throughput.r, max(throughput.g, throughput.b)), 0.95);
      if (!(rand01() < q)) break;
      throughput /= q;
    }
  }
  return result;
}

void main() {
  ivec2 pixel = ivec2(params.tile.xy + gl_GlobalInvocationID.xy);
  uint width = params.image.x;
  uint height = params.image.y;
  if (pixel.x >= int(width) || pixel.y >= int(height)) return;
  uint pixelIndex = uint(pixel.y) * width + uint(pixel.x);
  uint firstSample = params.image.z;
  uint samples = params.image.w;

  precise vec4 sum = imageLoad(sumImage, pixel);
  precise vec4 comp = imageLoad(compensationImage, pixel);
  for (uint k = 0u; k < samples; ++k) {
    rngState = pcgHash(pcgHash(pcgHash(params.tile.z) + pixelIndex) + firstSample + k);
    loopBudget = kPtLoopBudget;
    // Box filter: a uniform point in the pixel's footprint. Image y grows upwards.
    vec2 jitter = vec2(rand01(), rand01());
    vec2 ndc = (vec2(pixel) + jitter) / vec2(width, height) * 2.0 - 1.0;
    vec3 dir = normalize(params.cameraForward.xyz + ndc.x * params.cameraRight.xyz +
                         ndc.y * params.cameraUp.xyz);
    vec4 value = vec4(radiance(params.cameraPosition.xyz, dir), 1.0);
    if (loopBudget == 0u) atomicAdd(truncatedPaths, 1u);
    // Kahan summation: float sums of thousands of samples keep their low bits.
    precise vec4 y = value - comp;
    precise vec4 next = sum + y;
    comp = (next - sum) - y;
    sum = next;
  }
  imageStore(sumImage, pixel, sum);
  imageStore(compensationImage, pixel, comp);
  float n = float(firstSample + samples);
  imageStore(outImage, pixel, vec4((sum.rgb - comp.rgb) / n, 1.0));
}
