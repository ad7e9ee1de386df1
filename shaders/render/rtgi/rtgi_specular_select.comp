#version 450 core
// rtgi stage "specular", its first dispatch: of the pixels that trace this frame,
// lists the specular ones (covered, a mirror or isSpecular: what the specular stage
// lights) for the stage's own dispatch, and writes the others' specular light, none.
// On llvmpipe an invocation of a shader as large as the specular stage costs about
// 0.2 us even when it returns at once: 11 ms a 256x256 frame for the pixels that are
// not specular. Listed, it runs on the specular pixels alone, packed into full SIMD
// vectors.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#define RTGI_PIXEL_LIST
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiTraceGroup) in;

layout(binding = kSpecularImage, rgba16f) uniform writeonly image2D specularOut;
layout(std430, binding = kSpecularListBinding) buffer SpecularList {
  PixelListHeader header;
  uint specularPixels[];
};

void main() {
  ivec2 px;
  if (!tracePixel(px)) return;
  bool covered = texelFetch(gPosition, px, 0).w > 0.5;
  float roughness = clamp(texelFetch(gNormal, px, 0).w, 0.0, 1.0);
  float metallic = texelFetch(gAlbedo, px, 0).a;
  if (!covered || !(roughness < kMirrorRoughness || isSpecular(metallic, roughness))) {
    imageStore(specularOut, px, vec4(0.0, 0.0, 0.0, 1.0));
    return;
  }
  uint slot = atomicAdd(header.count.x, 1u);
  specularPixels[slot] = uint(px.x) | (uint(px.y) << 16u);
  // Work groups for the stage's dispatch, at most 65535 a row (tracePixel reads
  // them row by row).
  uint groups = slot / kRtgiTraceGroup + 1u;
  atomicMax(header.groups.x, min(groups, 65535u));
  atomicMax(header.groups.y, (groups + 65534u) / 65535u);
}
