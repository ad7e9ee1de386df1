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

// --- directions towards a triangle, uniform in solid angle ------------------------------
// Below this solid angle (sr), float loses the spherical triangle's shape (its angles
// are differences of nearly equal numbers): sample the triangle's area instead, which
// is as good there, as a small triangle's points are almost equally far and oblique.
VOXGI_CONST float kMinSphericalTriangle = 1e-2f;

// Solid angle of the spherical triangle with unit corners a, b, c (Van Oosterom and
// Strackee 1983, "The solid angle of a plane triangle"): exact for small triangles,
// where the sum of its angles minus pi is not.
VOXGI_FN float sphericalTriangleArea(vec3 a, vec3 b, vec3 c) {
  float num = abs(dot(a, cross(b, c)));
  float den = 1.0f + dot(a, b) + dot(b, c) + dot(c, a);
  return 2.0f * atan(num, den);
}

// The unit component of v orthogonal to unit a (0 where v is along a).
VOXGI_FN vec3 orthogonalUnit(vec3 v, vec3 a) {
  vec3 w = v - a * dot(v, a);
  float len2 = dot(w, w);
  return len2 > 1e-30f ? w * inversesqrt(len2) : vec3(0.0f);
}

// A direction uniform over the spherical triangle with unit corners a, b, c and solid
// angle `area` (sphericalTriangleArea), from two uniform numbers: Arvo 1995,
// "Stratified sampling of spherical triangles". u.x chooses the sub-triangle a, b, c'
// of area u.x * area (c' on the arc from a to c), u.y a point on the arc from b to c'.
VOXGI_FN vec3 sampleSphericalTriangle(vec3 a, vec3 b, vec3 c, float area, vec2 u) {
  // The angle at a, between the arcs towards b and towards c.
  vec3 tb = orthogonalUnit(b, a);
  vec3 tc = orthogonalUnit(c, a);
  float cosAlpha = clamp(dot(tb, tc), -1.0f, 1.0f);
  float sinAlpha = sqrt(max(0.0f, 1.0f - cosAlpha * cosAlpha));
  float cosC = dot(a, b);  // the arc from a to b
  float phi = u.x * area - acos(cosAlpha);
  float s = sin(phi);
  float t = cos(phi);
  float uu = t - cosAlpha;
  float vv = s + sinAlpha * cosC;
  float den = (vv * s + uu * t) * sinAlpha;
  float q = den != 0.0f ? clamp(((vv * t - uu * s) * cosAlpha - vv) / den, -1.0f, 1.0f) : 1.0f;
  vec3 cHat = a * q + tc * sqrt(max(0.0f, 1.0f - q * q));
  float z = 1.0f - u.y * (1.0f - dot(cHat, b));
  z = clamp(z, -1.0f, 1.0f);
  return normalize(b * z + orthogonalUnit(cHat, b) * sqrt(max(0.0f, 1.0f - z * z)));
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_SAMPLING_SHARED_H
