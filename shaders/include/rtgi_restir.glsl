// Reservoir resampling of the emitters' direct light at the pixels (ReSTIR DI:
// Bitterli et al. 2020, "Spatiotemporal reservoir resampling for real-time ray
// tracing with dynamic direct lighting"), for scenes of many emitters
// (RTGI_EMITTERS_SAMPLED). rtgi_direct.comp runs it in two dispatches:
//   RTGI_RESTIR_INITIAL  kRestirCandidates emitters drawn from the light tree, and,
//                        after a camera or mesh move, the reservoir the pixel it was
//                        kept last frame: one kept (temporal reuse);
//   RTGI_RESTIR          that reservoir and those of kRestirNeighbours pixels nearby
//                        that show a like surface: one kept (spatial reuse), shaded
//                        with one direction and one shadow ray (emitterShade), and
//                        kept for the next frame.
// A reservoir's sample is an emitter (its index), its target h the luminance of that
// emitter's exact unshadowed contribution at the surface (emitterTarget); a
// direction on it is drawn only to shade. Its contribution weight W stands in for
// 1 / the probability of the emitter, M counts the candidates behind it. Temporal
// reuse weighs each input i with h(y_i) W_i M_i and gives the result the weight
// sum / (Z h(y)), where Z sums the M_i of the inputs whose own surface could have
// drawn y (h_i(y) > 0): Bitterli et al.'s unbiased combination (their Algorithm 6).
// Spatial reuse weighs its inputs by pairwise MIS (restirDirect), also unbiased:
// a neighbour across an edge, whose surface faces other emitters, neither darkens
// nor brightens the pixel. A light tree draw costs 10-12 node tests on the way down;
// a reused reservoir three targets, so reuse adds candidates at a fraction of their
// price.
//
// Storage (kRtgiReservoirBinding): vec4 per pixel, (emitter index as float bits,
// W, M, the frame it was written as float bits); pixels [0, n) hold this frame's
// reservoirs after temporal reuse, [n, 2n) the final ones of the frame each pixel
// last traced.
#ifndef VOXGI_RTGI_RESTIR_GLSL
#define VOXGI_RTGI_RESTIR_GLSL

layout(std430, binding = kRtgiReservoirBinding) buffer Reservoirs { vec4 reservoirs[]; };

// Light-tree candidates a pixel draws each frame.
const int kRestirCandidates = 2;
// After a camera or mesh move, the last frame's reservoir counts at most this many
// times this frame's candidates (Bitterli et al. use 20): the light it keeps fades
// within that many frames once it no longer serves. A still camera reuses none: its
// pixels' running means already average every frame, and a reservoir carried from
// frame to frame makes their samples alike, so the mean converges more slowly (the
// hall's direct light at 64 frames: FLIP 0.100 against 0.103 without, yet 44% of
// its 16x16 blocks off by more than 3% against 34%, and 0.6% brighter).
const float kRestirHistory = 20.0;
// Neighbours reused, and the radius they are drawn from as a share of the image's
// height (Bitterli et al.: 30 pixels at 1080), at least kRestirMinRadius pixels.
const int kRestirNeighbours = 8;
const float kRestirRadius = 0.03;
const float kRestirMinRadius = 2.0;

struct Reservoir {
  int y;       // the emitter kept, -1: none
  float h;     // its target at this pixel's surface
  vec3 spec;   // its highlight there (lighting.glsl)
  float wSum;  // the weights streamed in
  float m;     // the candidates behind it
};

Reservoir emptyReservoir() {
  Reservoir r;
  r.y = -1;
  r.h = 0.0;
  r.spec = vec3(0.0);
  r.wSum = 0.0;
  r.m = 0.0;
  return r;
}

// Streams in sample y of target h (at this surface) with weight w, behind m
// candidates: kept with probability w / the sum so far.
void stream(inout Reservoir r, int y, float h, vec3 spec, float w, float m) {
  r.m += m;
  if (!(w > 0.0)) return;
  r.wSum += w;
  if (rand01() * r.wSum < w) {
    r.y = y;
    r.h = h;
    r.spec = spec;
  }
}

uint reservoirIndex(ivec2 px, bool final) {
  return uint(px.y) * rtgi.frame.z + uint(px.x) + (final ? rtgi.frame.z * rtgi.frame.w : 0u);
}

vec4 packReservoir(int y, float w, float m) {
  return vec4(intBitsToFloat(y), w, m, uintBitsToFloat(rtgi.frame.x));
}

// Streams in a stored reservoir (y, W, M as packed), its M capped at `maxM`; returns
// the M it counted. An index past the emitters (a buffer from before a scene
// change) counts as none.
float streamStored(inout Reservoir r, vec4 stored, Surface s, float maxM) {
  float m = min(stored.z, maxM);
  if (!(m > 0.0)) return 0.0;
  int y = floatBitsToInt(stored.x);
  if (y < 0 || y >= int(rtgi.counts.y) || !(stored.y > 0.0)) {
    r.m += m;  // candidates that found no light count all the same
    return m;
  }
  vec3 spec;
  float h = emitterTarget(y, s, spec);
  stream(r, y, h, spec, h * stored.y * m, m);
  return m;
}

// The contribution weight of r's sample: its weight sum / (Z h(y)).
float contributionWeight(Reservoir r, float z) {
  return r.y >= 0 && r.h > 0.0 && z > 0.0 ? r.wSum / (z * r.h) : 0.0;
}

// Whether a surface at position p with normal n, seen from the camera, is like s
// (the reprojection's test, rtgi_reproject.comp): within 25 degrees, and p within
// `plane` of s's distance from the camera off its tangent plane.
bool likeSurface(Surface s, vec3 p, vec3 n, float plane) {
  return dot(n, s.n) > 0.9 && abs(dot(p - s.p, s.n)) < plane * length(s.p - rtgi.camera.xyz);
}

#ifdef RTGI_RESTIR_INITIAL
layout(binding = kGPreviousPositionUnit) uniform sampler2D previousPosition;
layout(binding = kGPreviousNormalUnit) uniform sampler2D previousNormal;
layout(binding = kGMotionUnit) uniform sampler2D gMotion;

// The pixel of last frame's G-buffer that showed s at px, after a move: s's point
// projected with the last frame's camera (after its motion when meshes moved);
// (-1, -1) when off the image.
ivec2 previousPixel(ivec2 px, Surface s) {
  mat4 previous = mat4(rtgi.previousViewProj[0], rtgi.previousViewProj[1], rtgi.previousViewProj[2],
                       rtgi.previousViewProj[3]);
  vec4 clip = previous * vec4(s.p + texelFetch(gMotion, px, 0).xyz, 1.0);
  if (!(clip.w > 0.0)) return ivec2(-1);
  ivec2 q = ivec2(floor((clip.xy / clip.w * 0.5 + 0.5) * vec2(rtgi.frame.zw)));
  return any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(rtgi.frame.zw))) ? ivec2(-1)
                                                                                      : q;
}

// This frame's candidates at px, and temporal reuse; into the first half.
void restirInitial(ivec2 px, Pixel p) {
  Surface s = p.s;
  if (p.roughness < kMirrorRoughness) s.f0 = vec3(0.0);
  Reservoir r = emptyReservoir();
  int emitterCount = int(rtgi.counts.y);
  for (int i = 0; i < kRestirCandidates && emitterCount > 0; ++i) {
    float pmf;
    int k = pickLightTree(rand01(), floatBitsToUint(rand01()), s.p, s.n, pmf);
    vec3 spec = vec3(0.0);
    float h = k >= 0 && pmf > 0.0 ? emitterTarget(k, s, spec) : 0.0;
    stream(r, k, h, spec, h > 0.0 ? h / pmf : 0.0, 1.0);
  }
  // The candidates' own surface can draw what they drew: they count in Z whole.
  float z = float(kRestirCandidates);
  bool moved = (rtgi.counts.z & kRtgiReprojecting) != 0u;
  ivec2 q = moved ? previousPixel(px, s) : ivec2(-1);
  if (q.x >= 0) {
    vec4 was = texelFetch(previousPosition, q, 0);
    vec4 wasN = texelFetch(previousNormal, q, 0);
    vec4 stored = reservoirs[reservoirIndex(q, true)];
    // Written in an earlier frame of this accumulation, on a like surface of the
    // same material (a disocclusion drops it).
    if (was.w == texelFetch(gPosition, px, 0).w && floatBitsToUint(stored.w) < rtgi.frame.x &&
        likeSurface(s, was.xyz, normalize(wasN.xyz), 0.01)) {
      float m = streamStored(r, stored, s, kRestirHistory * float(kRestirCandidates));
      // Z: whether the surface it was made for could have drawn the sample kept.
      Surface t = s;
      t.p = was.xyz;
      t.n = normalize(wasN.xyz);
      vec3 spec;
      if (r.y >= 0 && emitterTarget(r.y, t, spec) > 0.0) z += m;
    }
  }
  reservoirs[reservoirIndex(px, false)] = packReservoir(r.y, contributionWeight(r, z), r.m);
}
#endif  // RTGI_RESTIR_INITIAL

#ifdef RTGI_RESTIR
// The surface at pixel q as the shadows stage shades it (a mirror takes no
// highlight from emitters: its reflected ray sees them).
Surface shadedSurface(ivec2 q) {
  Pixel p = loadPixel(q);
  if (p.roughness < kMirrorRoughness) p.s.f0 = vec3(0.0);
  return p.s;
}

// Spatial reuse at px, then the emitters' light: the result's estimate, shadowed.
// Keeps the final reservoir for the next frame.
//
// The neighbours' samples are weighed by pairwise MIS (Bitterli 2022, Lin et al.
// 2022 "Generalized resampled importance sampling"), which needs no more targets
// than the count of Bitterli et al.'s Algorithm 6 and bounds what a neighbour
// brings: the pixel (canonical, c) and each of its k neighbours i form a pair, whose
// balance heuristic, with the pixel's confidence split k ways, shares 1/k of the
// weight. Neighbour i's sample y_i weighs
//   m_i(y_i) h_c(y_i) W_i,  m_i(x) = M_i h_i(x) / (M_i h_i(x) + M_c/k h_c(x)) / k,
// the pixel's own y_c weighs m_c(y_c) h_c(y_c) W_c with m_c the sum of the pairs'
// other shares, and the result's W is the sum / h_c(y). The weights sum to 1 wherever
// h_c > 0, so the estimate is unbiased. Where a sample lights a neighbour little
// (h_i small: its W_i large) but this pixel strongly, as next to a small lamp, the
// weight stays what that neighbour's own reservoir holds; normalising by the count
// instead (1/Z) turned such samples into fireflies: 3x the noise after 16 frames
// beside small lamps (DirectLightTest).
vec3 restirDirect(ivec2 px, Surface s, vec3 o, vec3 ng) {
  vec4 own = reservoirs[reservoirIndex(px, false)];
  int yc = floatBitsToInt(own.x);
  float wc = own.y;
  float mc = max(own.z, 0.0);
  if (yc >= int(rtgi.counts.y) || !(wc > 0.0)) yc = -1;
  vec3 specC = vec3(0.0);
  float hcc = yc >= 0 ? emitterTarget(yc, s, specC) : 0.0;
  // The neighbours that traced this frame, on a like surface.
  ivec2 near[kRestirNeighbours];
  int k = 0;
  ivec2 size = ivec2(rtgi.frame.zw);
  for (int i = 0; i < kRestirNeighbours; ++i) {
    float a = 2.0 * kPi * rand01();
    float rad = max(kRestirRadius * float(rtgi.frame.w), kRestirMinRadius) * sqrt(rand01());
    ivec2 q = px + ivec2(round(rad * vec2(cos(a), sin(a))));
    if (q == px || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
    vec4 qp = texelFetch(gPosition, q, 0);
    if (qp.w < 0.5) continue;
    vec4 stored = reservoirs[reservoirIndex(q, false)];
    if (floatBitsToUint(stored.w) != rtgi.frame.x || !(stored.z > 0.0) ||
        !likeSurface(s, qp.xyz, normalize(texelFetch(gNormal, q, 0).xyz), 0.05))
      continue;
    near[k++] = q;
  }
  Reservoir r = emptyReservoir();
  float share = k > 0 ? 0.0 : 1.0;  // m_c(y_c)
  float mck = mc / float(max(k, 1));
  for (int i = 0; i < k; ++i) {
    Surface t = shadedSurface(near[i]);
    vec4 stored = reservoirs[reservoirIndex(near[i], false)];
    int yi = floatBitsToInt(stored.x);
    float mi = stored.z;
    if (yi >= int(rtgi.counts.y) || !(stored.y > 0.0)) yi = -1;
    vec3 spec = vec3(0.0), unused;
    float hci = 0.0, weight = 0.0;
    if (yi >= 0) {
      hci = emitterTarget(yi, s, spec);
      float hii = mi * emitterTarget(yi, t, unused);
      float d = hii + mck * hci;
      weight = d > 0.0 ? hii / d / float(k) * hci * stored.y : 0.0;
    }
    stream(r, yi, hci, spec, weight, mi);
    if (yc >= 0) {
      float hic = mi * emitterTarget(yc, t, unused);
      float d = hic + mck * hcc;
      share += d > 0.0 ? mck * hcc / d / float(k) : 0.0;
    }
  }
  stream(r, yc, hcc, specC, yc >= 0 ? share * hcc * wc : 0.0, mc);
  float w = r.y >= 0 && r.h > 0.0 ? r.wSum / r.h : 0.0;
  reservoirs[reservoirIndex(px, true)] = packReservoir(r.y, w, r.m);
  if (r.y < 0 || !(w > 0.0)) return vec3(0.0);
  return emitterShade(r.y, w, r.spec * w, s, o, ng);
}
#endif  // RTGI_RESTIR

#endif  // VOXGI_RTGI_RESTIR_GLSL
