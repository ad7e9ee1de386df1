#version 450 core
// rtgi stage "shadows", first step where the light tree draws among all the scene's
// emitters at once (more than RtgiPass::Settings::exactEmitters, at most
// kLightTreeLeafDraw): light tiles. For each 8x8 tile of pixels, a distribution over
// the emitters, and kLightTileSamples emitters drawn from it; each pixel of the tile
// then takes its candidates among those (rtgi_direct_light.glsl,
// RTGI_EMITTER_TILES) and resamples them by its own bound on each, instead of
// weighing every emitter at its own point.
// - The tiles of tiled shading (Olsson and Assarsson 2011, "Tiled shading"), holding
//   a distribution over the emitters instead of a list of them, and the presampled
//   light tiles of Wyman and Panteleev 2021 ("Rearchitecting spatiotemporal
//   resampling for production", HPG), drawn from it.
// - The distribution mixes two: half each emitter's bound over the whole tile
//   (lightNodeRegionImportance, over the sphere that holds the tile's points and the
//   cone that holds its normals), which is 0 only where no pixel of the tile can
//   take the emitter's light, so the draw stays unbiased; half the emitters' own
//   bounds at one pixel of each quadrant of the tile (another each frame), which
//   follow what lights the tile's pixels more closely than a bound over all of them.
// One workgroup of kLightTileSize lanes per tile, lane i for its row i: a software
// rasterizer runs the eight lanes as one SIMD vector, where a workgroup of one lane
// per pixel would switch between eight at every barrier.
#include "rtgi_shared.h"
#include "light_tree_shared.h"

// What the pass reads of rtgi's parameters and G-buffer (as rtgi_common.glsl
// declares them).
layout(std140, binding = kRtgiParamsBinding) uniform RtgiBlock { RtgiParams rtgi; };
layout(binding = kGPositionUnit) uniform sampler2D gPosition;
layout(binding = kGNormalUnit) uniform sampler2D gNormal;

layout(local_size_x = kLightTileSize) in;
layout(std430, binding = kLightTreeBinding) readonly buffer LightTree { GpuLightNode lightTree[]; };
GpuLightNode lightTreeNode(int i) { return lightTree[i]; }
// Tile t's kLightTileSamples emitters at t x kLightTileSamples: each its place among
// the light tree's leaves and the probability it was drawn with (float bits); 0, 0
// where no emitter can light the tile.
layout(std430, binding = kRtgiReservoirBinding) writeonly buffer LightTiles { uvec2 lightTiles[]; };

const uint kTilePixels = kLightTileSize * kLightTileSize;
const int kMaxTileEmitters = int(kLightTreeLeafDraw);
// The share of the distribution that follows the sampled pixels' own bounds.
const float kPixelShare = 0.5;
const int kTileSamples = 4;          // pixels sampled per tile, one per quadrant
shared vec4 tilePoint[kTilePixels];  // xyz position, w 1 where the pixel shows a surface
shared vec3 tileNormal[kTilePixels];
shared vec3 rowLow[kLightTileSize], rowHigh[kLightTileSize], rowNormal[kLightTileSize];
shared float rowCos[kLightTileSize];
shared bool rowCovered[kLightTileSize];
shared vec4 tileSphere;  // xyz centre, w radius: every covered pixel's point lies inside
shared vec4 tileCone;    // xyz unit axis, w cosine of the normals' half-angle about it
shared int samplePixel[kTileSamples];  // -1 where the quadrant shows no surface
// The bounds: over the tile (row 0), then at each sampled pixel; row 0 ends as the
// mixed distribution's running sums.
shared float tileWeights[kTileSamples + 1][kMaxTileEmitters];
shared float lanePartial[kLightTileSize][kTileSamples + 1];

void main() {
  uint lane = gl_LocalInvocationIndex;
  uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  // This lane's row: its pixels, their bounding box and summed normals.
  vec3 lo = vec3(3.4e38), hi = vec3(-3.4e38), sum = vec3(0.0);
  bool any = false;
  for (uint x = 0u; x < kLightTileSize; ++x) {
    ivec2 px = ivec2(gl_WorkGroupID.xy * kLightTileSize + uvec2(x, lane));
    bool inside = px.x < int(rtgi.width) && px.y < int(rtgi.height);
    vec4 pos = inside ? texelFetch(gPosition, px, 0) : vec4(0.0);
    bool covered = pos.w > 0.5;
    // The normal as loadPixel makes it.
    vec3 n = covered ? normalize(texelFetch(gNormal, px, 0).xyz) : vec3(0.0);
    tilePoint[lane * kLightTileSize + x] = vec4(pos.xyz, covered ? 1.0 : 0.0);
    tileNormal[lane * kLightTileSize + x] = n;
    if (covered) {
      lo = min(lo, pos.xyz);
      hi = max(hi, pos.xyz);
      sum += n;
      any = true;
    }
  }
  rowLow[lane] = lo;
  rowHigh[lane] = hi;
  rowNormal[lane] = sum;
  rowCovered[lane] = any;
  barrier();
  // Every lane merges the rows alike (no barrier needed for a result all share).
  lo = vec3(3.4e38);
  hi = vec3(-3.4e38);
  sum = vec3(0.0);
  any = false;
  for (uint r = 0u; r < kLightTileSize; ++r) {
    if (!rowCovered[r]) continue;
    lo = min(lo, rowLow[r]);
    hi = max(hi, rowHigh[r]);
    sum += rowNormal[r];
    any = true;
  }
  if (!any) return;  // no pixel of the tile draws an emitter (the same for every lane)
  float len = length(sum);
  vec3 axis = len > 1e-3 ? sum / len : vec3(0.0, 0.0, 1.0);
  float cosN = len > 1e-3 ? 1.0 : -1.0;
  for (uint x = 0u; x < kLightTileSize; ++x) {
    uint i = lane * kLightTileSize + x;
    if (tilePoint[i].w != 0.0) cosN = min(cosN, dot(tileNormal[i], axis));
  }
  rowCos[lane] = cosN;
  // Lanes below kTileSamples each pick a pixel of their quadrant, another each frame.
  if (lane < uint(kTileSamples)) {
    const uint halfSize = kLightTileSize / 2u;
    uint h = pcgHash(pcgHash(rtgi.seed ^ 0x7f4a7c15u) + tile * 977u + rtgi.frameIndex * 31u + lane);
    uint start = h & (halfSize * halfSize - 1u);
    int picked = -1;
    for (uint j = 0u; j < halfSize * halfSize && picked < 0; ++j) {
      uint k = (start + j) & (halfSize * halfSize - 1u);
      uint x = (lane & 1u) * halfSize + k % halfSize, y = (lane >> 1u) * halfSize + k / halfSize;
      if (tilePoint[y * kLightTileSize + x].w != 0.0) picked = int(y * kLightTileSize + x);
    }
    samplePixel[lane] = picked;
  }
  barrier();
  for (uint r = 0u; r < kLightTileSize; ++r) cosN = min(cosN, rowCos[r]);
  vec3 c = 0.5 * (lo + hi);
  vec3 extent = max(abs(lo), abs(hi));
  // Widened against the rounding of the centre, of the distances to it and of the
  // normals' cosines.
  float radius = 0.5 * length(hi - lo) * 1.0001 + 1e-6 * max(extent.x, max(extent.y, extent.z));
  cosN = max(cosN - 1e-4, -1.0);

  GpuLightNode root = lightTree[0];
  int begin = int(root.info.z);
  int count = min(int(root.info.w), kMaxTileEmitters);
  // Each lane its share of the emitters, each leaf read once; the rows' sums by lane.
  float partial[kTileSamples + 1];
  for (int r = 0; r <= kTileSamples; ++r) partial[r] = 0.0;
  for (int k = int(lane); k < count; k += int(kLightTileSize)) {
    GpuLightNode leaf = lightTree[begin + k];
    float w = lightNodeRegionImportance(leaf, c, radius, axis, cosN);
    tileWeights[0][k] = w;
    partial[0] += w;
    for (int r = 1; r <= kTileSamples; ++r) {
      int s = samplePixel[r - 1];
      w = s < 0 ? 0.0 : lightNodeImportance(leaf, tilePoint[s].xyz, tileNormal[s]);
      tileWeights[r][k] = w;
      partial[r] += w;
    }
  }
  for (int r = 0; r <= kTileSamples; ++r) lanePartial[lane][r] = partial[r];
  barrier();
  float rowTotal[kTileSamples + 1];
  for (int r = 0; r <= kTileSamples; ++r) {
    rowTotal[r] = 0.0;
    for (uint l = 0u; l < kLightTileSize; ++l) rowTotal[r] += lanePartial[l][r];
  }
  int rows = 0;
  for (int r = 1; r <= kTileSamples; ++r)
    if (rowTotal[r] > 0.0) ++rows;
  float regionShare = rows > 0 ? 1.0 - kPixelShare : 1.0;
  float pixelShare = rows > 0 ? kPixelShare / float(rows) : 0.0;
  for (int k = int(lane); k < count; k += int(kLightTileSize)) {
    float w = 0.0;
    if (rowTotal[0] > 0.0) {
      w = regionShare * tileWeights[0][k] / rowTotal[0];
      for (int r = 1; r <= kTileSamples; ++r)
        if (rowTotal[r] > 0.0) w += pixelShare * tileWeights[r][k] / rowTotal[r];
    }
    tileWeights[0][k] = w;
  }
  barrier();
  if (lane == 0u) {
    float total = 0.0;
    for (int k = 0; k < count; ++k) {
      total += tileWeights[0][k];
      tileWeights[0][k] = total;
    }
  }
  barrier();
  // The tile's emitters, stratified: sample j's uniform number lies in
  // [j, j + 1) / kLightTileSamples.
  float total = tileWeights[0][count - 1];
  for (uint j = lane; j < kLightTileSamples; j += kLightTileSize) {
    uvec2 entry = uvec2(0u);
    if (total > 0.0) {
      uint h =
          pcgHash(pcgHash(rtgi.seed ^ 0x2545f491u) + tile * 131u + rtgi.frameIndex * 7919u + j);
      float x = (float(j) + float(h >> 8u) * (1.0 / 16777216.0)) / float(kLightTileSamples) * total;
      int a = 0, b = count - 1;  // the first running sum above x
      while (a < b) {
        int mid = (a + b) / 2;
        if (tileWeights[0][mid] > x)
          b = mid;
        else
          a = mid + 1;
      }
      float weight = tileWeights[0][a] - (a > 0 ? tileWeights[0][a - 1] : 0.0);
      if (weight > 0.0) entry = uvec2(uint(a), floatBitsToUint(weight / total));
    }
    lightTiles[tile * kLightTileSamples + j] = entry;
  }
}
