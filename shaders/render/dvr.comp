#version 450 core
// `--mode dvr`: direct volume rendering of the octree. Each pixel's camera ray walks
// the occupied leaves front to back and composites what each voxel emits and
// reflects (its injected light and bounces) by its opacity (coverage), until the
// ray is opaque (rtgi.cameraForward.w) or leaves the grid. The voxel paper's view of
// the lit volume itself, blocky by design.
#include "scene_shared.h"
#include "lighting.glsl"
#include "octree.glsl"
#include "rtgi_shared.h"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;
layout(std140, binding = kRtgiParamsBinding) uniform RtgiBlock { RtgiParams rtgi; };
layout(std430, binding = kOctreeRadianceBinding) readonly buffer Radiance { uint radiance[]; };
layout(std430, binding = kOctreeMaterialBinding) readonly buffer Material { uvec2 material[]; };
layout(std430, binding = kOctreeEmissionBinding) readonly buffer Emission { uint emission[]; };
layout(binding = kAccumImage, rgba32f) uniform writeonly image2D outImage;

const int kMaxLeaves = 64;  // leaves composited per ray at most

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (px.x >= int(rtgi.width) || px.y >= int(rtgi.height)) return;
  vec2 ndc = (vec2(px) + 0.5) / vec2(rtgi.width, rtgi.height) * 2.0 - 1.0;
  vec3 dir =
      normalize(rtgi.cameraForward.xyz + ndc.x * rtgi.cameraRight.xyz + ndc.y * rtgi.cameraUp.xyz);
  MarchRay r = octreeWorldRay(rtgi.camera.xyz, dir, 3.0e38);
  MarchState s;
  vec3 color = vec3(0.0);
  float alpha = 0.0;
  if (marchBegin(r, 0.0, octreeRootSize(), s)) {
    for (int k = 0; k < kMaxLeaves && alpha < rtgi.cameraForward.w; ++k) {
      MarchHit h = octreeFirstHit(r, octreeDepth(), s, kRaySteps);
      if (!h.hit) break;
      float a = unpackUnorm4x8(material[h.node].x).a;
      vec3 c = unpackRgb9e5(radiance[lightSlot(h.node, material[h.node].y, -dir)]) +
               unpackRgb9e5(emission[h.node]);
      color += (1.0 - alpha) * a * c;
      alpha += (1.0 - alpha) * a;
      if (!marchExitCell(r, 1, octreeRootSize(), s)) break;
    }
  }
  imageStore(outImage, px, vec4(color, 1.0));
}
