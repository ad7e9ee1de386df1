// Reservoir resampling of the emitters' direct light at the pixels (ReSTIR DI:
// Bitterli et al. 2020, "Spatiotemporal reservoir resampling for real-time ray
// tracing with dynamic direct lighting"), for scenes of many emitters
// (RTGI_EMITTERS_SAMPLED). rtgi_direct.comp runs it in two dispatches:
//   RTGI_RESTIR_INITIAL  kRestirCandidates emitters drawn from the light tree: one
//                        kept, by resampled importance sampling, in a reservoir;
//   RTGI_RESTIR          that reservoir and those of kRestirNeighbours pixels nearby
//                        that show a like surface: one kept (spatial reuse), shaded
//                        with one direction and one shadow ray (emitterShade).
// A reservoir's sample is an emitter (its index), its target h the luminance of that
// emitter's exact unshadowed contribution at the surface (emitterTarget); a
// direction on it is drawn only to shade. Its contribution weight W stands in for
// 1 / the probability of the emitter, M counts the candidates behind it
// (kRestirCandidates for every pixel's own reservoir). Reuse
// weighs its inputs by pairwise MIS (restirDirect): unbiased, so a neighbour across
// an edge, whose surface faces other emitters, neither darkens nor brightens the
// pixel. A light tree draw costs a few node tests on the way down and a bound for
// each emitter of the node it ends in; a reused reservoir two targets, so reuse
// adds candidates at a fraction of their price.
//
// No temporal reuse: each pixel's running mean already averages its frames (after a
// camera move, its reprojected history), and a reservoir carried from frame to frame
// makes their samples alike, so the mean converges more slowly. The hall's direct
// light at 64 still frames: FLIP 0.100 with the last frame's reservoir merged in
// (its M capped at 20x, as Bitterli et al.), 0.103 without, but 44% of its 16x16
// blocks off by more than 3% against 34%, and 0.6% brighter; after a 10-degree
// orbit of the gallery view, FLIP 0.114/0.119/0.113 against 0.111/0.116/0.108
// without (seeds 7, 8, 9).
//
// Storage (kRtgiReservoirBinding): vec4 per pixel, (emitter index as float bits,
// W, its target h at the pixel's own surface, the frame it was written as float
// bits).
#ifndef VOXGI_RTGI_RESTIR_GLSL
#define VOXGI_RTGI_RESTIR_GLSL

layout(std430, binding = kRtgiReservoirBinding) buffer Reservoirs { vec4 reservoirs[]; };

// Light-tree candidates a pixel draws each frame, each walking down to nodes of at
// most kRestirLeafDraw emitters (RtgiPass::Settings::restirCandidates,
// candidateLeafDraw): a draw among a node's emitters costs a bound for each, so small
// nodes make candidates cheap, and resampling by the exact target makes up for
// their looser distribution.
#ifndef RTGI_RESTIR_CANDIDATES
#define RTGI_RESTIR_CANDIDATES 4
#endif
const int kRestirCandidates = RTGI_RESTIR_CANDIDATES;
// The candidates of a pixel whose highlight is sharp (a glossy pixel below
// kSampledHighlightAlpha: RtgiPass::Settings::glossyCandidates). Its target peaks at
// the emitters its lobe sees, which the tree's bounds know nothing of, so a few
// candidates seldom hold them, and the one that does is a firefly. Those pixels are
// few (the hall's bronze knot, 4% of the image: its `shadows` +14%).
#ifndef RTGI_GLOSSY_CANDIDATES
#define RTGI_GLOSSY_CANDIDATES 16
#endif
const int kGlossyCandidates = RTGI_GLOSSY_CANDIDATES;
#ifndef RTGI_RESTIR_LEAF_DRAW
#define RTGI_RESTIR_LEAF_DRAW 8.0
#endif
const float kRestirLeafDraw = RTGI_RESTIR_LEAF_DRAW;
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

uint reservoirIndex(ivec2 px) { return uint(px.y) * rtgi.width + uint(px.x); }

vec4 packReservoir(int y, float w, float h) {
  return vec4(intBitsToFloat(y), w, h, uintBitsToFloat(rtgi.frameIndex));
}

// The emitter a stored reservoir holds, -1 for none (or an index past the emitters:
// a buffer from before a scene change).
int storedEmitter(vec4 stored) {
  int y = floatBitsToInt(stored.x);
  return y < int(rtgi.emitterCount) && stored.y > 0.0 ? y : -1;
}

// Whether a surface at position p with normal n, seen from the camera, is like s
// (the reprojection's test, rtgi_reproject.comp): within 25 degrees, and p within
// `plane` of s's distance from the camera off its tangent plane.
bool likeSurface(Surface s, vec3 p, vec3 n, float plane) {
  return dot(n, s.n) > 0.9 && abs(dot(p - s.p, s.n)) < plane * length(s.p - rtgi.camera.xyz);
}

#ifdef RTGI_RESTIR_INITIAL
// This frame's candidates at px.
void restirInitial(ivec2 px, Pixel p) {
  Surface s = p.s;
  if (p.roughness < kMirrorRoughness) s.f0 = vec3(0.0);
  Reservoir r = emptyReservoir();
  int emitterCount = int(rtgi.emitterCount);
  bool sharp = p.roughness >= kMirrorRoughness && isSpecular(p.metallic, p.roughness) &&
               s.specular > 0.0 && !sampledHighlight(s);
  int candidates = sharp ? kGlossyCandidates : kRestirCandidates;
  for (int i = 0; i < candidates && emitterCount > 0; ++i) {
    float pmf;
    int k = pickLightTree(rand01(), floatBitsToUint(rand01()), s.p, s.n, kRestirLeafDraw, pmf);
    vec3 spec = vec3(0.0);
    float h = k >= 0 && pmf > 0.0 ? emitterTarget(k, s, spec) : 0.0;
    stream(r, k, h, spec, h > 0.0 ? h / pmf : 0.0, 1.0);
  }
  float w = r.y >= 0 ? r.wSum / (r.m * r.h) : 0.0;
  reservoirs[reservoirIndex(px)] = packReservoir(r.y, w, r.h);
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
  vec4 own = reservoirs[reservoirIndex(px)];
  int yc = storedEmitter(own);
  float wc = own.y;
  const float mc = float(kRestirCandidates), mi = mc;
  vec3 specC = vec3(0.0);
  float hcc = yc >= 0 ? emitterTarget(yc, s, specC) : 0.0;
  // The neighbours that traced this frame, on a like surface.
  ivec2 near[kRestirNeighbours];
  int k = 0;
  ivec2 size = ivec2(rtgi.width, rtgi.height);
  for (int i = 0; i < kRestirNeighbours; ++i) {
    float a = 2.0 * kPi * rand01();
    float rad = max(kRestirRadius * float(rtgi.height), kRestirMinRadius) * sqrt(rand01());
    ivec2 q = px + ivec2(round(rad * vec2(cos(a), sin(a))));
    if (q == px || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
    vec4 qp = texelFetch(gPosition, q, 0);
    if (qp.w < 0.5) continue;
    vec4 stored = reservoirs[reservoirIndex(q)];
    if (floatBitsToUint(stored.w) != rtgi.frameIndex ||
        !likeSurface(s, qp.xyz, normalize(texelFetch(gNormal, q, 0).xyz), 0.05))
      continue;
    near[k++] = q;
  }
  Reservoir r = emptyReservoir();
  float share = k > 0 ? 0.0 : 1.0;  // m_c(y_c)
  float mck = mc / float(max(k, 1));
  for (int i = 0; i < k; ++i) {
    Surface t = shadedSurface(near[i]);
    vec4 stored = reservoirs[reservoirIndex(near[i])];
    int yi = storedEmitter(stored);
    vec3 spec = vec3(0.0), unused;
    float hci = 0.0, weight = 0.0;
    if (yi >= 0) {
      hci = emitterTarget(yi, s, spec);
      float hii = mi * stored.z;  // its target at its own surface, kept by the first pass
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
  if (r.y < 0 || !(w > 0.0)) return vec3(0.0);
  return emitterShade(r.y, w, r.spec * w, s, o, ng);
}
#endif  // RTGI_RESTIR

#endif  // VOXGI_RTGI_RESTIR_GLSL
