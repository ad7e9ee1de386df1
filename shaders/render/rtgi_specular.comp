#version 450 core
// rtgi stage "specular": light along the reflection. Mirrors (roughness below
// kMirrorRoughness) trace the reflected ray and see the light the voxel it hits
// reflects, or an emitter's exact geometry where the ray meets one first (a light
// the size of its voxels would look too big); glossy surfaces trace one ray per frame towards a GGX micro-normal
// drawn from the visible normals (Heitz 2018) and see reflected light only (their
// highlight from the lights comes from the shadows stage). Weighted by Schlick's
// Fresnel. Dielectrics rougher than kGlossyRoughness are skipped.
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
    }
  }
  imageStore(specularOut, px, vec4(result, 1.0));
}
