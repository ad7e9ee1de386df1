// Voxel cone tracing (Crassin, Neyret, Sainz, Green, Eisemann, "Interactive Indirect
// Illumination Using Voxel Cone Tracing", Pacific Graphics 2011): rtgi's indirect
// stage with `--indirect cones`. A few wide cones over the hemisphere replace the
// one random ray: each walks the octree's filtered inner levels (octree_filter.comp:
// opacity the mean of the 8 children's, colours opacity-weighted means), the level
// at each step the one whose cells match the cone's diameter there, and composites
// the radiance it meets front to back by opacity. Deterministic: the same light
// every frame, and biased where the filtered levels mix what a ray would keep
// apart; nodes that mix both sides of a wall are kept dark (coneNode) so that light
// does not leak through it, and a coarse level's cells show as blocks (one cell
// is read per level, not interpolated: docs/rtgi.md#cone-tracing).
//
// Include after octree.glsl and sampling.glsl, with the octree's radiance[] and
// material[] declared.
#ifndef VOXGI_RTGI_CONES_GLSL
#define VOXGI_RTGI_CONES_GLSL

// Six cones of 60 degrees' aperture, one along the normal and five around it, 60
// degrees off it, 72 degrees apart. Their weights split the cosine-weighted
// hemisphere: a cap of half-angle 30 degrees holds sin^2(30 deg) = 1/4 of it, the
// rest (3/4) is shared by the five side cones, 0.15 each. They sum to 1, so a
// uniform light L gives albedo x L, as the ray estimate does.
const int kCones = 6;
const float kConeHalfTan = 0.57735027;  // tan(30 deg)
const float kConeAxisWeight = 0.25;
const float kConeSideWeight = 0.15;
// A step is this share of the cone's diameter where it is; the opacity of a sample
// is corrected for it (1 - (1 - a)^(step / diameter)).
const float kConeStep = 0.5;
const int kConeMaxSteps = 48;
// A cone stops once this opaque.
const float kConeOpaque = 0.95;

// A node as the cone sees it: the radiance it reflects times the share of the
// cone's cross-section it covers, and that share. The octree's voxels are surface
// voxels: a plane across a node of s^3 leaves fills s^2 of them, so its mean
// opacity is about 1/s of the plane's. The count of leaves over s^2 (the mean times
// s) is the share of the node's face they would cover as one layer: what a cone
// crossing the node sees of them (at most 1).
// Which way its surfaces face: a node whose normal points along the cone shows its
// back (seenFromBehind) and is passed over: it neither lights nor occludes. Else
// the voxels of the surface a cone leaves, which its wide footprint takes in, would
// shade it (the side cones graze it); a closed surface still stops the cone where
// its front faces it. An inner node whose children's normals disagree (their mean
// shorter than 1/2: both sides of a wall, a whole sphere) occludes but gives no
// light: its filtered light mixes what the cone sees with what lies behind it (the
// outside of a wall lit from outside), the leak of isotropic filtering. A leaf
// keeps the rays' rule (its light counts unless seen from behind).
vec4 coneNode(uint node, float size, vec3 dir) {
  if (VOXGI_NODE(node) == 0u) return vec4(0.0);
  uvec2 m = material[node];
  if (seenFromBehind(m.y, dir)) return vec4(0.0);
  float a = min(1.0, unpackUnorm4x8(m.x).a * size);
  vec3 n = leafNormal(m.y);
  bool lights = size <= 1.0 || dot(n, n) > 0.25;
  return vec4(lights ? unpackRgb9e5(radiance[lightSlot(node, m.y, -dir)]) * a : vec3(0.0), a);
}

// The octree at voxel v, at `level` and the level above (coarser): one descent
// for both. Outside the root cube, or under an empty node: nothing.
void coneLookup(ivec3 v, int level, vec3 dir, out vec4 fine, out vec4 coarse) {
  fine = vec4(0.0);
  coarse = vec4(0.0);
  int depth = octreeDepth();
  if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, ivec3(octreeRootSize())))) return;
  int reached;
  uint parent = octreeLookup(depth, v, level - 1, reached);
  if (reached < level - 1) return;
  coarse = coneNode(parent, float(1 << (depth - level + 1)), dir);
  uint first = VOXGI_NODE(parent);
  if (first == 0u) return;
  fine = coneNode(first + childIndex(v, depth, level - 1), float(1 << (depth - level)), dir);
}

// The radiance arriving at o (world) within the cone about unit dir whose half-angle
// has tangent halfTan: samples front to back, each at the level of detail of the
// cone's diameter there (in voxels, log2 of it: 0 is the leaves), blended between
// the two levels about it.
vec3 coneRadiance(vec3 o, vec3 dir, float halfTan) {
  int depth = octreeDepth();
  float rootSize = float(octreeRootSize());
  vec3 g0 = octreeToGrid(o);
  vec3 color = vec3(0.0);
  float alpha = 0.0;
  float t = 0.5;  // voxels; o is already off the surface (surfaceRayOrigin)
  for (int k = 0; k < kConeMaxSteps && alpha < kConeOpaque; ++k) {
    float diameter = max(1.0, 2.0 * halfTan * t);
    vec3 g = g0 + dir * t;
    if (any(lessThan(g, vec3(-diameter))) || any(greaterThan(g, vec3(rootSize + diameter)))) break;
    float lod = clamp(log2(diameter), 0.0, float(depth - 1));
    int level = depth - int(floor(lod));
    vec4 fine, coarse;
    coneLookup(ivec3(floor(g)), level, dir, fine, coarse);
    vec4 s = mix(fine, coarse, lod - floor(lod));
    float step = kConeStep * diameter;
    if (s.a > 0.0) {
      // The sample's opacity stands for a cell as deep as the diameter; the step
      // crosses `step` of it.
      float a = 1.0 - pow(max(1.0 - s.a, 0.0), step / diameter);
      color += (1.0 - alpha) * s.rgb * (a / s.a);
      alpha += (1.0 - alpha) * a;
    }
    t += step;
  }
  return color;
}

// Diffuse irradiance over pi at o about the unit normal n, as the weighted cones see
// it (the mean incoming radiance, cosine-weighted): times the albedo, the diffuse
// indirect light. `ng`: the surface's own normal (or 0); cones below it bring
// nothing, as rays do not (no leaks under normal maps).
vec3 coneIrradiance(vec3 o, vec3 n, vec3 ng) {
  vec3 t, b;
  basis(n, t, b);
  vec3 sum = vec3(0.0);
  for (int i = 0; i < kCones; ++i) {
    vec3 dir = n;
    float w = kConeAxisWeight;
    if (i > 0) {
      float phi = float(i - 1) * (6.2831853 / 5.0);
      // 60 degrees off the normal: sin 60 = 0.866, cos 60 = 0.5.
      dir = normalize(0.8660254 * (cos(phi) * t + sin(phi) * b) + 0.5 * n);
      w = kConeSideWeight;
    }
    if (ng != vec3(0.0) && dot(dir, ng) < 0.0) continue;
    sum += w * coneRadiance(o, dir, kConeHalfTan);
  }
  return sum;
}

// Glossy reflection by one cone about the mirror direction (Crassin et al. 2011,
// section 4.2), its aperture following the GGX roughness alpha = roughness^2: half
// of the distribution of micro-normals lies within atan(alpha) of the normal
// (D's cosine-weighted mass within theta is tan^2 / (alpha^2 + tan^2)), and a
// reflection turns twice as far as the micro-normal, so the cone's half-angle is
// 2 atan(alpha), at most the diffuse cones' 30 degrees. The tangent of that
// double angle: 2 alpha / (1 - alpha^2).
float glossyConeHalfTan(float alpha) {
  float a = min(alpha, 0.26794919);  // tan(15 deg): a 30-degree half-angle
  return 2.0 * a / (1.0 - a * a);
}

#endif  // VOXGI_RTGI_CONES_GLSL
