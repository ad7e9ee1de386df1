#version 450 core
// rtgi stage "reproject": the first stage of a frame after the camera or meshes
// moved. Each pixel's running mean follows the surface it shows: the surface point
// of this frame's G-buffer, where it was last frame (its motion, from the meshes'
// previous vertices), is projected with the previous frame's camera, and the history
// there is read from the four previous pixels around it (bilinear weights), keeping
// only those that showed the same surface: the same material (the G-buffer's object
// id: a lamp and the ceiling around it are coplanar), normals within 25 degrees,
// and the point on their tangent plane within 1% of its distance from the camera. What
// fails the test everywhere (a disocclusion) starts again with a count of 0.
//
// The count (alpha) is the pixel's history length; while the camera moves it is
// capped (rtgi.historyCap frames; fewer, glossyHistory and mirrorHistory, for glossy
// surfaces and mirrors, whose light changes with the view; edgeHistory at edges), so
// the image follows the view within a few frames; once the camera stops, accumulation goes on
// without a cap, as before. Reads the accumulation target (as kHistoryUnit) and writes the
// reprojected mean into its own image, which accumulate (RTGI_REPROJECTED) reads in its place.
#include "scene_shared.h"
#include "lighting.glsl"
#include "sampling.glsl"
#include "octree.glsl"
#include "rtgi_common.glsl"

layout(local_size_x = kRtgiGroupX, local_size_y = kRtgiGroupY) in;

layout(std430, binding = kMaterialBinding) readonly buffer Materials { GpuMaterial materials[]; };
layout(binding = kHistoryUnit) uniform sampler2D history;
layout(binding = kGPreviousPositionUnit) uniform sampler2D previousPosition;
layout(binding = kGPreviousNormalUnit) uniform sampler2D previousNormal;
layout(binding = kGMotionUnit) uniform sampler2D gMotion;
layout(binding = kReprojectedImage, rgba32f) uniform writeonly image2D reprojected;
#ifdef RTGI_MOMENTS
// The denoiser's moments and mean of the direct term (rtgi_accumulate.comp) follow
// the mean.
layout(binding = kHistoryMomentsUnit) uniform sampler2D historyMoments;
layout(binding = kHistoryDirectUnit) uniform sampler2D historyDirect;
layout(binding = kReprojectedMomentsImage, rgba32f) uniform writeonly image2D reprojectedMoments;
layout(binding = kReprojectedDirectImage, rgba32f) uniform writeonly image2D reprojectedDirect;
#endif

void store(ivec2 px, vec4 mean, vec4 m, vec3 direct) {
  imageStore(reprojected, px, mean);
#ifdef RTGI_MOMENTS
  imageStore(reprojectedMoments, px, m);
  imageStore(reprojectedDirect, px, vec4(direct, 0.0));
#endif
}

// The history a pixel of this material keeps across a camera move.
float historyCap(float metallic, float roughness) {
  if ((rtgi.flags & kRtgiHasSpecular) == 0u || isLambertian(metallic, roughness))
    return rtgi.historyCap;
  return roughness < kMirrorRoughness ? rtgi.mirrorHistory : rtgi.glossyHistory;
}

// Whether the material of a covered G-buffer texel (w: 1 + its index) emits.
bool emits(float w) {
#ifdef VOXGI_NO_EMISSION
  return false;
#else
  return any(greaterThan(materials[int(w) - 1].emission, vec3(0.0)));
#endif
}

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(rtgi.width, rtgi.height);
  if (px.x >= size.x || px.y >= size.y) return;
  vec4 p = texelFetch(gPosition, px, 0);
  if (p.w < 0.5) {
    store(px, vec4(0.0), vec4(0.0), vec3(0.0));  // nothing drawn: nothing to keep
    return;
  }
  vec4 nr = texelFetch(gNormal, px, 0);
  vec3 n = normalize(nr.xyz);
  mat4 previous = mat4(rtgi.previousViewProj[0], rtgi.previousViewProj[1], rtgi.previousViewProj[2],
                       rtgi.previousViewProj[3]);
  // Where the point was: moving meshes moved it since (motion: 0 elsewhere).
  vec3 was = p.xyz + texelFetch(gMotion, px, 0).xyz;
  vec4 clip = previous * vec4(was, 1.0);
  vec3 sum = vec3(0.0), direct = vec3(0.0);
  vec4 moments = vec4(0.0);
  float count = 0.0, weight = 0.0;
  bool edge = false, lampEdge = false;
  if (clip.w > 0.0) {
    // Pixel q covers [q, q + 1): its centre is at q + 0.5.
    vec2 at = (clip.xy / clip.w * 0.5 + 0.5) * vec2(size) - 0.5;
    ivec2 base = ivec2(floor(at));
    vec2 t = at - vec2(base);
    float tolerance = 0.01 * length(p.xyz - rtgi.camera.xyz);
    for (int k = 0; k < 4; ++k) {
      ivec2 q = base + ivec2(k & 1, k >> 1);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      vec4 qp = texelFetch(previousPosition, q, 0);
      vec3 qn = normalize(texelFetch(previousNormal, q, 0).xyz);
      // Not covered or another material; another surface.
      if (qp.w != p.w || !(dot(qn, n) > 0.9) || !(abs(dot(qp.xyz - was, n)) < tolerance)) {
        edge = true;
        lampEdge = lampEdge || (qp.w > 0.5 && emits(qp.w));
        continue;
      }
      vec4 h = texelFetch(history, q, 0);
      if (!(h.a > 0.0)) continue;
      float w = ((k & 1) != 0 ? t.x : 1.0 - t.x) * ((k >> 1) != 0 ? t.y : 1.0 - t.y);
      sum += w * h.rgb;
#ifdef RTGI_MOMENTS
      moments += w * texelFetch(historyMoments, q, 0);
      direct += w * texelFetch(historyDirect, q, 0).rgb;
#endif
      count += w * h.a;
      weight += w;
    }
  }
  // A sliver of one tap's weight would carry its light alone: below 1% of the
  // bilinear footprint the pixel starts again.
  if (!(weight > 0.01)) {
    store(px, vec4(0.0), vec4(0.0), vec3(0.0));
    return;
  }
  vec4 am = texelFetch(gAlbedo, px, 0);
  float cap = historyCap(am.a, clamp(nr.w, 0.0, 1.0));
  // At an edge the history kept mixes both sides in proportions of the old pixel
  // grid: it is kept short, and the edge converges again from this frame's samples.
  // Along an emitter's edge, whose light outshines what surrounds it many times
  // over, none is kept.
  if (edge) cap = lampEdge || emits(p.w) ? 0.0 : min(cap, rtgi.edgeHistory);
  float n1 = min(count / weight, cap);
  if (n1 > 0.0)
    store(px, vec4(sum / weight, n1), moments / weight, direct / weight);
  else
    store(px, vec4(0.0), vec4(0.0), vec3(0.0));
}
