#version 450 core
// rtgi stage "accumulate": emission + direct + indirect + specular of this frame,
// averaged with the frames before it while camera and scene stay still (a running
// mean in float: the n-th sample of a pixel adds (c - mean) / n; alpha holds n).
// Pixels that traced nothing this frame (interleaving) keep their mean. A
// non-finite term is dropped rather than poisoning the mean. VOXGI_NO_EMISSION
// (effect plan) leaves emission out.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#define RTGI_TRACED_IMAGE
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;

layout(binding = kDirectImage, rgba16f) uniform readonly image2D directIn;
layout(binding = kIndirectImage, rgba16f) uniform readonly image2D indirectIn;
layout(binding = kSpecularImage, rgba16f) uniform readonly image2D specularIn;
layout(binding = kAccumImage, rgba32f) uniform image2D accum;

vec3 finite(vec3 c) { return mix(c, vec3(0.0), bvec3(uvec3(isnan(c)) | uvec3(isinf(c)))); }

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (outside(px)) return;
#ifdef VOXGI_NO_EMISSION
  vec3 c = vec3(0.0);
#else
  vec3 c = finite(texelFetch(gEmission, px, 0).rgb);
#endif
  uint flags = rtgi.counts.z;
  if ((flags & kRtgiHasDirect) != 0u) c += finite(imageLoad(directIn, px).rgb);
  if ((flags & kRtgiHasIndirect) != 0u) c += finite(imageLoad(indirectIn, px).rgb);
  if ((flags & kRtgiHasSpecular) != 0u) c += finite(imageLoad(specularIn, px).rgb);
  vec4 previous = rtgi.frame.x > 0u ? imageLoad(accum, px) : vec4(0.0);
  float n = previous.a + 1.0;
  vec3 mean = previous.rgb + (c - previous.rgb) / n;
  imageStore(accum, px, vec4(mean, n));
}
