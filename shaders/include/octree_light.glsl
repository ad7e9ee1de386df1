// Direct light with visibility marched through the octree: shadow rays, emitters
// chosen by power, points on emitters. Shared by light injection (irradiance at a
// voxel) and rtgi (reflected radiance at a pixel). Include after octree.glsl,
// scene_shared.h, lighting.glsl and sampling.glsl.
#ifndef VOXGI_OCTREE_LIGHT_GLSL
#define VOXGI_OCTREE_LIGHT_GLSL

layout(std430, binding = kLightBinding) readonly buffer Lights { GpuLight lights[]; };
layout(std430, binding = kEmitterBinding) readonly buffer Emitters { GpuEmitter emitters[]; };
layout(std430, binding = kOctreeLightCdfBinding) readonly buffer EmitterCdf { float emitterCdf[]; };

// 1 if no voxel lies on the segment from p along unit dir, dist world units long,
// between startVoxels and dist - endVoxels (in voxels).
float octreeVisible(vec3 p, vec3 dir, float dist, float startVoxels, float endVoxels) {
  float tEnd = min(dist / octreeVoxelSize(), 3.0e38) - endVoxels;
  if (!(tEnd > startVoxels)) return 1.0;
  MarchHit h = octreeTrace(octreeWorldRay(p, dir, tEnd), startVoxels, kRaySteps);
  return h.hit ? 0.0 : 1.0;
}

// Direction and distance from p to a punctual light (directional: infinite).
void punctualDirection(GpuLight light, vec3 p, out vec3 l, out float dist) {
  if (uint(light.positionType.w) == kLightDirectional) {
    l = -normalize(light.directionRange.xyz);
    dist = 3.0e38;
  } else {
    vec3 d = light.positionType.xyz - p;
    dist = length(d);
    l = dist > 0.0 ? d / dist : vec3(0.0, 1.0, 0.0);
  }
}

// An emitter drawn with probability proportional to its power.
int pickEmitter(float u, int count, out float pmf) {
  int lo = 0, hi = count - 1;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (emitterCdf[mid] > u)
      hi = mid;
    else
      lo = mid + 1;
  }
  pmf = emitterCdf[lo] - (lo > 0 ? emitterCdf[lo - 1] : 0.0);
  return lo;
}

// A point on the emitter, uniform over its area (a cluster: its disk).
vec3 emitterPoint(GpuEmitter e, vec2 u) {
  if (e.kind == kEmitterCluster) {
    vec3 t, bt;
    basis(e.b, t, bt);
    float r = sqrt(e.area / kPi) * sqrt(u.x);
    float phi = 2.0 * kPi * u.y;
    return e.a + r * (cos(phi) * t + sin(phi) * bt);
  }
  float s = sqrt(u.x);
  return e.a * (1.0 - s) + e.b * (s * (1.0 - u.y)) + e.c * (s * u.y);
}

// How far off its surface a point drawn on emitter e may lie (emitterPoint): a
// cluster's points lie on its disk, up to its radius from the facets.
float emitterSlack(GpuEmitter e) { return e.kind == kEmitterCluster ? sqrt(e.area / kPi) : 0.0; }

// A direction from p (normal n) towards a point of emitter e that emits towards p,
// from two uniform numbers: returns its solid-angle pdf (0: no such point), the
// direction l and the distance to the point. Triangles that p sees under at least
// kMinSphericalTriangle: the part above p's horizon, about in proportion to the
// cosine there (sampleClippedTriangle, sampling_shared.h: Arvo 1995 warped after
// Hart et al. 2020), so the Lambert estimate below hardly varies over the triangle,
// however large and near it is, and no draw is spent below the horizon (a skylight
// over a column's face: half the draws black, the rest twice as bright, before).
// Smaller triangles and clusters (disks): uniform over their area, pdf = dist^2 /
// (area x cosine at the emitter).
float sampleEmitterDirection(GpuEmitter e, vec3 p, vec3 n, vec2 u, out vec3 l, out float dist) {
  l = vec3(0.0);
  dist = 0.0;
  bool twoSided = e.twoSided != 0u;
  bool cluster = e.kind == kEmitterCluster;
  vec3 ne = cluster ? e.b : cross(e.b - e.a, e.c - e.a);
  float ne2 = dot(ne, ne);
  if (!(ne2 > 0.0)) return 0.0;
  ne *= inversesqrt(ne2);
  if (!cluster) {
    vec3 a = e.a - p, b = e.b - p, c = e.c - p;
    float la = length(a), lb = length(b), lc = length(c);
    if (la > 0.0 && lb > 0.0 && lc > 0.0 &&
        sphericalTriangleArea(a / la, b / lb, c / lc) >= kMinSphericalTriangle) {
      float pdf = sampleClippedTriangle(a, b, c, n, u, l);
      if (!(pdf > 0.0)) return 0.0;
      float cosE = -dot(ne, l);
      float toPlane = dot(e.a - p, ne);  // -(p's height above the plane)
      if (twoSided) {
        cosE = abs(cosE);
      } else if (!(cosE > 0.0)) {
        return 0.0;  // p is behind a one-sided emitter
      }
      if (!(cosE > 1e-6)) return 0.0;
      dist = abs(toPlane) / cosE;
      return pdf;
    }
  }
  vec3 d = emitterPoint(e, u) - p;
  float dist2 = dot(d, d);
  if (!(dist2 > 0.0)) return 0.0;
  dist = sqrt(dist2);
  l = d / dist;
  float cosE = -dot(ne, l);
  if (twoSided) cosE = abs(cosE);
  float area = emitterArea(e);
  if (!(cosE > 1e-6) || !(area > 0.0)) return 0.0;
  return dist2 / (area * cosE);
}

// The shadow ray from p (a leaf's, facing n; unoriented: n = 0) to a random point of
// emitter e: its direction l and length dist; false where the draw reaches no point
// that lights p (it counts as shadowed). The leaf's light from e is its exact
// unshadowed irradiance times the share of these rays that are clear, which is the
// share of that irradiance arriving only if the rays are drawn in proportion to it:
// facing n, about so (sampleEmitterDirection: the part of the triangle above the
// horizon, in proportion to the cosine); unoriented, uniform over the emitter's area.
// Drawn uniformly over the area, a 16 x 4 m skylight half hidden by a gallery's slab
// lit what stood under it by the area it showed, not by the light it sent: the day
// hall's voxel bounces came out 4.6% bright.
bool leafEmitterRay(GpuEmitter e, vec3 p, vec3 n, out vec3 l, out float dist) {
  if (dot(n, n) > 0.0)
    return sampleEmitterDirection(e, p, n, vec2(rand01(), rand01()), l, dist) > 0.0;
  vec3 d = emitterPoint(e, vec2(rand01(), rand01())) - p;
  dist = length(d);
  l = dist > 0.0 ? d / dist : vec3(0.0);
  return true;
}

// Visibility of emitter e from p (a leaf's, facing n) through one shadow ray to a
// random point on it (leafEmitterRay).
float emitterVisible(GpuEmitter e, vec3 p, vec3 n, float startVoxels) {
  vec3 l;
  float dist;
  if (!leafEmitterRay(e, p, n, l, dist)) return 0.0;
  if (!(dist > 0.0)) return 1.0;
  return octreeVisible(p, l, dist, startVoxels, kSurfaceOffsetVoxels);
}

// Where the ray from o along unit d meets emitter e's emitting side (a cluster: its
// disk), or a negative value.
float emitterHit(GpuEmitter e, vec3 o, vec3 d) {
  bool twoSided = e.twoSided != 0u;
  if (e.kind == kEmitterCluster) {
    vec3 n = e.b;
    float dn = dot(d, n);
    if (!(abs(dn) > 1e-12) || (!twoSided && dn > 0.0)) return -1.0;
    float t = dot(e.a - o, n) / dn;
    vec3 q = o + d * t - e.a;
    return dot(q, q) <= e.area / kPi ? t : -1.0;
  }
  vec3 e1 = e.b - e.a;
  vec3 e2 = e.c - e.a;
  vec3 pv = cross(d, e2);
  float det = dot(e1, pv);
  // det = -dot(d, cross(e1, e2)): positive when the ray meets the side the winding
  // faces, the side a one-sided emitter lights.
  if (!(abs(det) > 1e-20) || (!twoSided && det < 0.0)) return -1.0;
  float inv = 1.0 / det;
  vec3 tv = o - e.a;
  float u = dot(tv, pv) * inv;
  vec3 qv = cross(tv, e1);
  float v = dot(d, qv) * inv;
  if (u < 0.0 || v < 0.0 || u + v > 1.0) return -1.0;
  return dot(e2, qv) * inv;
}

// Radiance of the nearest emitter the ray meets before `tMax` (world units), exact
// geometry rather than voxels: a mirror shows a light its own size.
vec3 emitterAlongRay(vec3 o, vec3 d, float tMax, int count) {
  vec3 radiance = vec3(0.0);
  float nearest = tMax;
  for (int k = 0; k < count; ++k) {
    float t = emitterHit(emitters[k], o, d);
    if (t > 0.0 && t < nearest) {
      nearest = t;
      radiance = emitters[k].radiance;
    }
  }
  return radiance;
}

#endif  // VOXGI_OCTREE_LIGHT_GLSL
