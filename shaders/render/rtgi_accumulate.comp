#version 450 core
// rtgi stage "accumulate": emission + direct + indirect + specular of this frame,
// averaged with the frames before it while camera and scene stay still (a running
// mean in float: frame k adds (c - mean) / (k + 1)). A non-finite term is dropped
// rather than poisoning the mean. VOXGI_NO_EMISSION (effect plan) leaves emission out.
#include "rtgi_shared.h"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;
layout(std140, binding = kRtgiParamsBinding) uniform RtgiBlock { RtgiParams rtgi; };
layout(binding = kGEmissionUnit) uniform sampler2D gEmission;
layout(binding = kDirectImage, rgba16f) uniform readonly image2D directIn;
layout(binding = kIndirectImage, rgba16f) uniform readonly image2D indirectIn;
layout(binding = kSpecularImage, rgba16f) uniform readonly image2D specularIn;
layout(binding = kAccumImage, rgba32f) uniform image2D accum;

vec3 finite(vec3 c) { return mix(c, vec3(0.0), bvec3(uvec3(isnan(c)) | uvec3(isinf(c)))); }

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (px.x >= int(rtgi.frame.z) || px.y >= int(rtgi.frame.w)) return;
#ifdef VOXGI_NO_EMISSION
  vec3 c = vec3(0.0);
#else
  vec3 c = finite(texelFetch(gEmission, px, 0).rgb);
#endif
  uint flags = rtgi.counts.z;
  if ((flags & kRtgiHasDirect) != 0u) c += finite(imageLoad(directIn, px).rgb);
  if ((flags & kRtgiHasIndirect) != 0u) c += finite(imageLoad(indirectIn, px).rgb);
  if ((flags & kRtgiHasSpecular) != 0u) c += finite(imageLoad(specularIn, px).rgb);
  float k = float(rtgi.frame.x);
  vec3 mean = k > 0.0 ? imageLoad(accum, px).rgb : vec3(0.0);
  mean += (c - mean) / (k + 1.0);
  imageStore(accum, px, vec4(mean, 1.0));
}
