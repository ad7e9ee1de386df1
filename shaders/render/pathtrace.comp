#version 450 core
// Reference path tracer over the exact triangles (see src/render/pathtrace_pass.h).
// One invocation owns one pixel and adds `samples per pass` paths to its running
// sum (Kahan-compensated), then writes the mean. Unidirectional path tracing with
// next-event estimation and multiple importance sampling (Veach 1997, power
// heuristic), Russian roulette, depths in Mitsuba's convention: the vertex the
// camera ray hits is depth 1; emission seen there is a path of depth 1, light
// gathered there by NEE a path of depth 2.
#include "scene_shared.h"
#include "pathtrace_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"

// Loop iterations this path may still run (see kPtLoopBudget).
uint loopBudget;

layout(local_size_x = kPtGroupX, local_size_y = kPtGroupY) in;

layout(std140, binding = kPtParamsBinding) uniform PtParamsBlock { GpuPtParams params; };
layout(std430, binding = kMaterialBinding) readonly buffer Materials { GpuMaterial materials[]; };
layout(std430, binding = kLightBinding) readonly buffer Lights { GpuLight lights[]; };
layout(binding = kPtNodeTexUnit) uniform usamplerBuffer nodeTexels;
layout(binding = kPtTriangleTexUnit) uniform usamplerBuffer triangleTexels;
layout(std430, binding = kPtShadingBinding) readonly buffer Shading { GpuPtShading shading[]; };
layout(std430, binding = kPtEmissiveBinding) readonly buffer Emissive { GpuPtEmissive emissive[]; };
layout(std430, binding = kPtCounterBinding) buffer Counters { uint truncatedPaths; };
#ifndef VOXGI_NO_TEXTURES
layout(std430, binding = kPtTextureBinding) readonly buffer Textures { uvec4 textures[]; };
layout(binding = kPtUvTexUnit) uniform usamplerBuffer uvTexels;
layout(binding = kPtTexelTexUnit) uniform usamplerBuffer textureTexels;
#endif
layout(binding = kPtSumImage, rgba32f) uniform image2D sumImage;
layout(binding = kPtCompensationImage, rgba32f) uniform image2D compensationImage;
layout(binding = kPtOutputImage, rgba32f) uniform writeonly image2D outImage;

const float kInf = 1.0 / 0.0;

#include "bvh_trace.glsl"

#ifndef VOXGI_NO_TEXTURES
// --- base-colour textures -------------------------------------------------------------
// Texture coordinates at barycentrics bc of triangle tri.
vec2 triangleUv(uint tri, vec2 bc) {
  vec4 a = uintBitsToFloat(texelFetch(uvTexels, int(tri) * 2));
  vec2 c = uintBitsToFloat(texelFetch(uvTexels, int(tri) * 2 + 1).xy);
  return (1.0 - bc.x - bc.y) * a.xy + bc.x * a.zw + bc.y * c;
}

vec4 srgbTexel(uvec4 t, ivec2 p) {
  vec4 c = unpackUnorm4x8(texelFetch(textureTexels, int(t.x) + p.y * int(t.y) + p.x).x);
  vec3 lo = c.rgb / 12.92, hi = pow((c.rgb + 0.055) / 1.055, vec3(2.4));
  return vec4(mix(hi, lo, lessThanEqual(c.rgb, vec3(0.04045))), c.a);
}

// Texture t at uv, bilinear over linear (decoded) texels, repeating as the raster
// sampler does. No mipmaps: paths jittered over the pixel average the footprint.
vec4 sampleTexture(uvec4 t, vec2 uv) {
  ivec2 size = ivec2(t.yz);
  uv = mix(uv, vec2(0.0), bvec2(uvec2(isnan(uv)) | uvec2(isinf(uv))));
  vec2 x = fract(uv) * vec2(size) - 0.5;  // in [-0.5, size - 0.5)
  vec2 f = x - floor(x);
  ivec2 i0 = ivec2(floor(x));  // -1 .. size - 1
  ivec2 a = i0 + size * ivec2(lessThan(i0, ivec2(0)));
  ivec2 b = a + 1 - size * ivec2(greaterThanEqual(a + 1, size));
  return mix(mix(srgbTexel(t, a), srgbTexel(t, ivec2(b.x, a.y)), f.x),
             mix(srgbTexel(t, ivec2(a.x, b.y)), srgbTexel(t, b), f.x), f.y);
}
#endif

// --- materials ----------------------------------------------------------------------
// Three kinds, as in scenes/reference_scenes.md: metallic 0 + roughness 1 is pure
// Lambert (albedo = base colour); metallic 1 + roughness 0 is a perfect mirror of
// reflectance = base colour, no Fresnel; anything else is the glTF metallic-roughness
// BRDF of lighting.glsl (Lambert + GGX, height-correlated Smith, Schlick's Fresnel).
const int kLambert = 0;
const int kMirror = 1;
const int kGgx = 2;

struct Bsdf {
  int kind;
  vec3 base;
  vec3 diffuse;
  vec3 f0;
  float alpha;
  float specularChance;  // probability of sampling the GGX lobe (kGgx only)
};

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

Bsdf makeBsdf(GpuMaterial m, float nv) {
  Bsdf b;
  float metallic = m.params.x;
  float roughness = m.params.y;
  b.base = m.baseColor.rgb;
  b.kind = isLambertian(metallic, roughness) ? kLambert
           : (metallic >= 1.0 && roughness <= 0.0) ? kMirror
                                                   : kGgx;
  b.diffuse = b.base * (1.0 - metallic);
  b.f0 = mix(vec3(0.04), b.base, metallic);
  b.alpha = clamp(roughness * roughness, 1e-3, 1.0);
  vec3 fv = b.f0 + (1.0 - b.f0) * pow(1.0 - nv, 5.0);
  float ws = luminance(fv);
  float wd = luminance(b.diffuse) * (1.0 - ws);
  b.specularChance = ws + wd > 0.0 ? clamp(ws / (ws + wd), 0.1, 1.0) : 1.0;
  if (wd <= 0.0) b.specularChance = 1.0;
  return b;
}

float smithG1(float nv, float alpha) {
  float a2 = alpha * alpha;
  return 2.0 * nv / (nv + sqrt(a2 + (1.0 - a2) * nv * nv));
}

// BSDF x cos(wi) and the pdf (solid angle) of sampling wi, for non-delta kinds.
vec3 evalBsdf(Bsdf b, vec3 n, vec3 wo, vec3 wi, out float pdf) {
  float nl = dot(n, wi);
  float nv = dot(n, wo);
  pdf = 0.0;
  if (nl <= 0.0 || nv <= 0.0) return vec3(0.0);
  if (b.kind == kLambert) {
    pdf = nl / kPi;
    return b.base * (nl / kPi);
  }
  vec3 h = normalize(wi + wo);
  float nh = max(dot(n, h), 0.0);
  float vh = max(dot(wo, h), 0.0);
  float d = ggxD(nh, b.alpha);
  vec3 f = b.f0 + (1.0 - b.f0) * pow(1.0 - vh, 5.0);
  vec3 spec = f * d * smithVisibility(nl, nv, b.alpha);
  vec3 diff = (1.0 - f) * b.diffuse / kPi;
  // Visible-normal sampling: pdf(wi) = G1(wo) D(h) / (4 n.wo).
  float pdfSpec = smithG1(nv, b.alpha) * d / (4.0 * nv);
  pdf = b.specularChance * pdfSpec + (1.0 - b.specularChance) * nl / kPi;
  return (spec + diff) * nl;
}


// Samples wi for a non-delta kind; false when the sample is below the surface.
bool sampleBsdf(Bsdf b, vec3 n, vec3 wo, out vec3 wi) {
  vec2 u = vec2(rand01(), rand01());
  if (b.kind == kLambert || rand01() >= b.specularChance) {
    wi = cosineSample(n, u);
  } else {
    vec3 t, bt;
    basis(n, t, bt);
    vec3 ve = vec3(dot(wo, t), dot(wo, bt), dot(wo, n));
    vec3 m = sampleVndf(ve, b.alpha, u);
    vec3 h = normalize(t * m.x + bt * m.y + n * m.z);
    wi = reflect(-wo, h);
  }
  return dot(n, wi) > 0.0;
}

// --- lights -------------------------------------------------------------------------
float powerHeuristic(float a, float b) {
  float a2 = a * a;
  return a2 / (a2 + b * b);
}

// One emissive triangle chosen by power (alias table), one point on it uniformly.
vec3 sampleEmissive(vec3 p, vec3 n, vec3 wo, Bsdf b, vec3 ng, float eps) {
  uint count = params.tile.w;
  float u = rand01() * float(count);
  uint i = min(uint(u), count - 1u);
  GpuPtEmissive e = emissive[i];
  if (u - float(i) >= e.v0.w) e = emissive[floatBitsToUint(e.e1.w)];
  float s = sqrt(rand01());
  float r = rand01();
  vec3 q = e.v0.xyz + e.e1.xyz * (s * (1.0 - r)) + e.e2.xyz * (s * r);
  vec3 c = cross(e.e1.xyz, e.e2.xyz);
  float area2 = length(c);
  vec3 nl = c / area2;
  vec3 toL = q - p;
  float dist2 = dot(toL, toL);
  float dist = sqrt(dist2);
  vec3 wi = toL / dist;
  float cosL = -dot(nl, wi);
  if (e.radiance.w > 0.5) cosL = abs(cosL);
  if (cosL <= 0.0 || !(dist > 0.0)) return vec3(0.0);
  float pdfBsdf;
  vec3 f = evalBsdf(b, n, wo, wi, pdfBsdf);
  if (f == vec3(0.0) || dot(ng, wi) <= 0.0) return vec3(0.0);
  float pdfLight = e.e2.w / (0.5 * area2) * dist2 / cosL;
  if (occluded(p + ng * eps, wi, dist * (1.0 - 1e-4) - eps)) return vec3(0.0);
  return f * e.radiance.rgb * (powerHeuristic(pdfLight, pdfBsdf) / pdfLight);
}

// Every punctual light (delta lights: NEE only), with its shadow ray.
vec3 samplePunctual(vec3 p, vec3 n, vec3 wo, Bsdf b, vec3 ng, float eps) {
  vec3 sum = vec3(0.0);
  int count = int(params.depth.z);
  for (int i = 0; i < count; ++i) {
    if (loopBudget == 0u) break;
    --loopBudget;
    GpuLight light = lights[i];
    uint type = uint(light.positionType.w);
    vec3 wi;
    float atten = 1.0;
    float dist = 1e30;
    if (type == kLightDirectional) {
      wi = -normalize(light.directionRange.xyz);
    } else {
      vec3 d = light.positionType.xyz - p;
      float dist2 = max(dot(d, d), 1e-30);
      dist = sqrt(dist2);
      wi = d / dist;
      atten = 1.0 / dist2;
      float range = light.directionRange.w;
      if (range > 0.0) {  // the glTF spec's recommended smooth window, as in raster
        float x = dist / range;
        atten *= clamp(1.0 - x * x * x * x, 0.0, 1.0);
      }
      if (type == kLightSpot) {
        float cd = dot(normalize(light.directionRange.xyz), -wi);
        atten *= smoothstep(light.cone.y, light.cone.x, cd);
      }
    }
    if (atten <= 0.0 || dot(ng, wi) <= 0.0) continue;
    float pdf;
    vec3 f = evalBsdf(b, n, wo, wi, pdf);
    if (f == vec3(0.0)) continue;
    if (occluded(p + ng * eps, wi, dist * (1.0 - 1e-4) - eps)) continue;
    sum += f * light.radiance.rgb * atten;
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
  float lastPdf = 0.0;  // solid-angle pdf of the BSDF sample that led here
  bool lastDelta = true;  // camera rays and mirror bounces: emission counts in full
  for (int depth = 1; depth <= maxDepth; ++depth) {
    if (loopBudget == 0u) break;
    --loopBudget;
    float t;
    uint tri;
    vec2 bc;
    if (!trace(o, d, kInf, false, t, tri, bc)) break;  // black background
    GpuPtTriangle T = loadTriangle(tri);
    GpuPtShading S = shading[tri];
    GpuMaterial m = materials[floatBitsToUint(S.n0.w)];
#ifndef VOXGI_NO_TEXTURES
    if ((m.flags & kMaterialHasTexture) != 0u)
      m.baseColor *= sampleTexture(textures[m.texture], triangleUv(tri, bc));
#endif
    vec3 p = T.v0.xyz + bc.x * T.e1.xyz + bc.y * T.e2.xyz;
    vec3 ng = normalize(cross(T.e1.xyz, T.e2.xyz));
    bool front = dot(ng, d) < 0.0;
    if (m.emission.rgb != vec3(0.0) && (front || (m.flags & kMaterialDoubleSided) != 0u)) {
      float w = 1.0;
      if (!lastDelta && lightsByNee && S.n1.w > 0.0) {
        float cosL = abs(dot(ng, d));
        float pdfLight = S.n1.w * t * t / max(cosL, 1e-20);
        w = powerHeuristic(lastPdf, pdfLight);
      }
      result += throughput * m.emission.rgb * w;
    }
    if (depth == maxDepth) break;

    // Shade on the side the ray arrived from.
    vec3 ns = normalize((1.0 - bc.x - bc.y) * S.n0.xyz + bc.x * S.n1.xyz + bc.y * S.n2.xyz);
    if (!front) {
      ng = -ng;
      ns = -ns;
    }
    vec3 wo = -d;
    if (dot(ns, wo) <= 0.0 || !(dot(ns, ns) > 0.5)) ns = ng;  // shading normal past the silhouette
    Bsdf b = makeBsdf(m, dot(ns, wo));
    if (b.kind != kGgx && b.base == vec3(0.0)) break;  // black: reflects nothing (the lights of the reference scenes)

    if (b.kind == kMirror) {
      d = reflect(d, ns);
      if (dot(d, ng) <= 0.0) break;
      throughput *= b.base;
      lastDelta = true;
    } else {
      if (lightsByNee) result += throughput * sampleEmissive(p, ns, wo, b, ng, eps);
      result += throughput * samplePunctual(p, ns, wo, b, ng, eps);
      vec3 wi;
      if (!sampleBsdf(b, ns, wo, wi) || dot(wi, ng) <= 0.0) break;
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
