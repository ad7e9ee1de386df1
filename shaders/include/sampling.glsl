// Random numbers and direction sampling shared by the Monte Carlo shaders
// (pathtrace, octree light injection and bounces, rtgi). Include after
// lighting.glsl (kPi).
#ifndef VOXGI_SAMPLING_GLSL
#define VOXGI_SAMPLING_GLSL

// --- random numbers ---------------------------------------------------------------
// PCG (RXS-M-XS 32) as a hash and as a stream (Jarzynski and Olano 2020, "Hash
// Functions for GPU Rendering"); each path gets its own stream from (seed, pixel,
// sample index), so samples never repeat across pixels, passes or runs.
uint rngState;

uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

float rand01() {
  rngState = rngState * 747796405u + 2891336453u;
  uint s = rngState;
  uint word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
  word = (word >> 22u) ^ word;
  return float(word >> 8u) * (1.0 / 16777216.0);  // [0, 1)
}

void basis(vec3 n, out vec3 t, out vec3 bt) {
  // Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);
  float b = n.x * n.y * a;
  t = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
  bt = vec3(b, s + n.y * n.y * a, -n.y);
}

vec3 cosineSample(vec3 n, vec2 u) {
  vec3 t, bt;
  basis(n, t, bt);
  float r = sqrt(u.x);
  float phi = 2.0 * kPi * u.y;
  return normalize(t * (r * cos(phi)) + bt * (r * sin(phi)) + n * sqrt(max(0.0, 1.0 - u.x)));
}

// Heitz 2018, "Sampling the GGX Distribution of Visible Normals"; ve in the local
// frame (z = normal). Returns the micro-normal.
vec3 sampleVndf(vec3 ve, float alpha, vec2 u) {
  vec3 vh = normalize(vec3(alpha * ve.x, alpha * ve.y, ve.z));
  float lensq = vh.x * vh.x + vh.y * vh.y;
  vec3 t1 = lensq > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
  vec3 t2 = cross(vh, t1);
  float r = sqrt(u.x);
  float phi = 2.0 * kPi * u.y;
  float p1 = r * cos(phi);
  float p2 = r * sin(phi);
  float s = 0.5 * (1.0 + vh.z);
  p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * p2;
  vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
  return normalize(vec3(alpha * nh.x, alpha * nh.y, max(1e-6, nh.z)));
}

#endif  // VOXGI_SAMPLING_GLSL
