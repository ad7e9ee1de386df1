// Random numbers and direction sampling, written once for GLSL and C++ (see
// shared_fn.h): the path tracer on both devices, octree light injection and
// bounces, rtgi. GLSL shaders reach these through sampling.glsl, which adds a
// per-invocation stream (rngState, rand01); the CPU path tracer calls them directly.
// Twin test: tests/render/shading_twin_gltest.cpp.
#ifndef VOXGI_SAMPLING_SHARED_H
#define VOXGI_SAMPLING_SHARED_H

#include "shared_fn.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// PCG (RXS-M-XS 32) as a hash and as a stream (Jarzynski and Olano 2020, "Hash
// Functions for GPU Rendering"); each path gets its own stream from (seed, pixel,
// sample index), so samples never repeat across pixels, passes or runs.
VOXGI_FN uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Advances the stream and returns a float in [0, 1) with 24 random bits.
VOXGI_FN float pcgNext01(VOXGI_INOUT(uint) state) {
  state = state * 747796405u + 2891336453u;
  uint s = state;
  uint word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
  word = (word >> 22u) ^ word;
  return float(word >> 8u) * (1.0f / 16777216.0f);
}

// Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
VOXGI_FN void basis(vec3 n, VOXGI_OUT(vec3) t, VOXGI_OUT(vec3) bt) {
  float s = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (s + n.z);
  float b = n.x * n.y * a;
  t = vec3(1.0f + s * n.x * n.x * a, s * b, -s * n.x);
  bt = vec3(b, s + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction about n from two uniform numbers.
VOXGI_FN vec3 cosineSample(vec3 n, vec2 u) {
  vec3 t;
  vec3 bt;
  basis(n, t, bt);
  float r = sqrt(u.x);
  float phi = 2.0f * kPi * u.y;
  return normalize(t * (r * cos(phi)) + bt * (r * sin(phi)) + n * sqrt(max(0.0f, 1.0f - u.x)));
}

// Heitz 2018, "Sampling the GGX Distribution of Visible Normals"; ve in the local
// frame (z = normal). Returns the micro-normal.
VOXGI_FN vec3 sampleVndf(vec3 ve, float alpha, vec2 u) {
  vec3 vh = normalize(vec3(alpha * ve.x, alpha * ve.y, ve.z));
  float lensq = vh.x * vh.x + vh.y * vh.y;
  vec3 t1 = lensq > 0.0f ? vec3(-vh.y, vh.x, 0.0f) * inversesqrt(lensq) : vec3(1.0f, 0.0f, 0.0f);
  vec3 t2 = cross(vh, t1);
  float r = sqrt(u.x);
  float phi = 2.0f * kPi * u.y;
  float p1 = r * cos(phi);
  float p2 = r * sin(phi);
  float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * sqrt(max(0.0f, 1.0f - p1 * p1)) + s * p2;
  vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return normalize(vec3(alpha * nh.x, alpha * nh.y, max(1e-6f, nh.z)));
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_SAMPLING_SHARED_H
