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

// A number in [0, 1) from the bits of point p: as good as a uniform draw for each
// point a jittered sample meets, and the same for the same point (the coverage of a
// blended surface in the raster passes; texture_shared.h's alphaHash for rays).
VOXGI_FN float pointHash01(vec3 p) {
  uint h =
      pcgHash(floatBitsToUint(p.x) ^ pcgHash(floatBitsToUint(p.y) ^ pcgHash(floatBitsToUint(p.z))));
  return float(h >> 8u) * (1.0f / 16777216.0f);
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

// --- directions towards a triangle above a receiver's horizon, about as its cosine --------
// Hart et al. 2020, "Practical product sampling by fitting and composing warps": the
// cosine at a receiver over a spherical triangle is close to the bilinear function of
// Arvo's two numbers (sampleSphericalTriangle) through its values at the corners, so
// drawing those numbers from that bilinear density before Arvo's map draws directions
// nearly in proportion to the cosine. Arvo's map sends (0, 0) and (1, 0) to corner b,
// (0, 1) to a and (1, 1) to c.

// A number in [0, 1) drawn from the density in proportion to (1 - t) w0 + t w1 (w0,
// w1 >= 0, not both 0), from uniform x.
VOXGI_FN float sampleLinear(float w0, float w1, float x) {
  return x * (w0 + w1) / (w0 + sqrt(mix(w0 * w0, w1 * w1, x)));
}

// Of a bilinear warp with corner weights w00 (u = 0, v = 0), w10, w01, w11 (>= 0, their
// sum > 0): the point u drawn from its density, which is returned.
VOXGI_FN float sampleBilinear(float w00, float w10, float w01, float w11, VOXGI_INOUT(vec2) u) {
  float v = sampleLinear(w00 + w10, w01 + w11, u.y);
  float x = sampleLinear(mix(w00, w01, v), mix(w10, w11, v), u.x);
  u = vec2(x, v);
  return 4.0f * mix(mix(w00, w10, x), mix(w01, w11, x), v) / (w00 + w10 + w01 + w11);
}

// Share of the largest corner cosine that each corner's weight is raised to, so the
// density stays above zero where the true cosine, not quite bilinear, is not.
VOXGI_CONST float kCosineWarpFloor = 0.1f;

// A direction towards the spherical triangle with unit corners a, b, c and solid angle
// `area`, drawn about in proportion to its cosine about n, from two uniform numbers;
// returns its solid-angle pdf. Corners below the horizon must not be given (see
// sampleClippedTriangle).
VOXGI_FN float sampleSphericalTriangleCosine(vec3 a, vec3 b, vec3 c, float area, vec3 n, vec2 u,
                                             VOXGI_OUT(vec3) l) {
  float ca = max(dot(a, n), 0.0f), cb = max(dot(b, n), 0.0f), cc = max(dot(c, n), 0.0f);
  float lift = kCosineWarpFloor * max(max(ca, cb), max(cc, 1e-6f));
  ca += lift;
  cb += lift;
  cc += lift;
  float density = sampleBilinear(cb, cb, ca, cc, u);
  l = sampleSphericalTriangle(a, b, c, area, u);
  return density / area;
}

// The solid angle, and the weight it is drawn by, of the spherical triangle of corners
// a, b, c (relative to the receiver, not unit) above the horizon of n: its solid angle
// x its mean corner cosine, the cosine-weighted solid angle's estimate.
VOXGI_FN float clippedPartWeight(vec3 a, vec3 b, vec3 c, vec3 n, VOXGI_OUT(float) area) {
  area = 0.0f;
  if (!(min(dot(a, a), min(dot(b, b), dot(c, c))) > 1e-20f)) return 0.0f;  // the receiver on it
  vec3 ua = normalize(a), ub = normalize(b), uc = normalize(c);
  area = sphericalTriangleArea(ua, ub, uc);
  float mean = (max(dot(ua, n), 0.0f) + max(dot(ub, n), 0.0f) + max(dot(uc, n), 0.0f)) / 3.0f;
  // A sliver too thin for Arvo's map in float is left out (its light with it: far
  // below the noise).
  return area > 1e-7f ? area * (mean + 1e-3f) : 0.0f;
}

// A direction towards the triangle a, b, c (corners relative to the receiver, which
// sees it under at least kMinSphericalTriangle) within the upper hemisphere of the
// receiver's normal n, drawn about in proportion to the cosine
// (sampleSphericalTriangleCosine), from two uniform numbers; returns its solid-angle
// pdf, 0 where no part of the triangle is above the horizon. The triangle is clipped
// to the hemisphere first: a triangle, or a quad cut into two triangles, one drawn
// in proportion to clippedPartWeight. Directions below the horizon bring a receiver
// nothing, so a uniform draw over a triangle the horizon cuts wastes its share of
// them and doubles the rest: black and white pixels.
VOXGI_FN float sampleClippedTriangle(vec3 a, vec3 b, vec3 c, vec3 n, vec2 u, VOXGI_OUT(vec3) l) {
  l = vec3(0.0f);
  float da = dot(a, n), db = dot(b, n), dc = dot(c, n);
  bool aUp = da > 0.0f, bUp = db > 0.0f, cUp = dc > 0.0f;
  int above = int(aUp) + int(bUp) + int(cUp);
  if (above == 0) return 0.0f;
  // Turn the corners (keeping their order) so that, with two above, c is the one below,
  // and with one above, a is the one above.
  int turns = (above == 2 ? !aUp : above == 1 && bUp)   ? 1
              : (above == 2 ? !bUp : above == 1 && cUp) ? 2
                                                        : 0;
  for (int k = 0; k < turns; ++k) {  // (a, b, c) -> (b, c, a)
    vec3 t = a;
    a = b;
    b = c;
    c = t;
    float s = da;
    da = db;
    db = dc;
    dc = s;
  }
  // The first part, and the second where the clipped polygon is a quad.
  vec3 p0 = a, p1 = b, p2 = c, q2 = c;
  if (above == 2) {
    p2 = b + (c - b) * (db / (db - dc));  // where b -> c crosses the horizon
    q2 = c + (a - c) * (dc / (dc - da));  // where c -> a crosses it
  } else if (above == 1) {
    p1 = a + (b - a) * (da / (da - db));
    p2 = a + (c - a) * (da / (da - dc));
  }
  float area0 = 0.0f, area1 = 0.0f;
  float w0 = clippedPartWeight(p0, p1, p2, n, area0);
  float w1 = above == 2 ? clippedPartWeight(p0, p2, q2, n, area1) : 0.0f;
  if (!(w0 + w1 > 0.0f)) return 0.0f;
  float pick0 = w0 / (w0 + w1);
  bool first = u.x < pick0;
  vec2 v = first ? vec2(u.x / pick0, u.y) : vec2((u.x - pick0) / (1.0f - pick0), u.y);
  v.x = min(v.x, 0.99999994f);
  float pdf = first ? pick0 * sampleSphericalTriangleCosine(normalize(p0), normalize(p1),
                                                            normalize(p2), area0, n, v, l)
                    : (1.0f - pick0) * sampleSphericalTriangleCosine(normalize(p0), normalize(p2),
                                                                     normalize(q2), area1, n, v, l);
  return pdf;
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_SAMPLING_SHARED_H
