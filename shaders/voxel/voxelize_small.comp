#version 450 core
// Voxelization, compute path for small triangles: one invocation per triangle of a
// draw whose projection reaches at most kSmallTriangleSpan pixel columns and rows
// (voxel_triangle.glsl; the raster's geometry stage drops exactly these). After
// Rauwendaal & Bailey, "Hybrid Computational Voxelization Using the Graphics
// Pipeline" (JCGT 2(1), 2013): the rasterizer pays set-up and binning per triangle
// however few pixels it covers, a compute invocation only the samples it tests.
//
// Coverage follows the raster's: the rasterizer's own 4 sample positions, vertices
// snapped to its sub-pixel grid, exact integer edge functions and a top-left rule
// for samples on an edge. Attributes are interpolated at the centroid of the
// covered samples (the pixel centre when all are covered), the base-colour texture
// with the triangle's own UV gradients. What a covered pixel adds to the grid is
// the fragment stage's code (voxel_fragment.glsl).
// Every other triangle of some area is passed on to the raster: its indices are
// appended to its group's range of the large-triangle indices and the group's
// indirect command counts them (voxel_shared.h). So each triangle is decided once,
// here.
// Effect-plan variants: VOXGI_NO_TEXTURES, VOXGI_NO_ALPHA, VOXGI_NO_EMISSION,
// VOXGI_NO_COLORS; tests:
// VOXGI_COUNT_SMALL counts the triangles taken.
#include "scene_shared.h"
#include "voxel_shared.h"

layout(local_size_x = kResolveGroupSize) in;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };
layout(std430, binding = kMaterialBinding) readonly buffer Materials { GpuMaterial materials[]; };
layout(location = kMaterialIndexLocation) uniform int materialIndex;
layout(location = kVoxelFirstIndexLocation) uniform uint firstIndex;
layout(location = kVoxelTriangleCountLocation) uniform uint triangleCount;
layout(location = kVoxelCommandLocation) uniform uint firstCommand;
layout(std430, binding = kLargeIndexBinding) writeonly buffer LargeIndices { uint largeIndices[]; };
layout(std430, binding = kDrawCommandBinding) buffer DrawCommands { uint drawCommands[]; };
layout(binding = kBaseColorUnit) uniform sampler2D baseColorTexture;
layout(binding = kEmissiveUnit) uniform sampler2D emissiveTexture;
// The scene's vertices (scene::Vertex, 40 bytes: 5 RG32F texels, position.xy,
// position.z normal.x, normal.yz, uv, uv2) and indices.
layout(binding = kVoxelVertexUnit) uniform samplerBuffer vertexData;
layout(binding = kVoxelIndexUnit) uniform usamplerBuffer indexData;
#ifndef VOXGI_NO_COLORS
// The vertex colours (one RGBA32F texel a vertex), read where hasColors is 1.
layout(binding = kVoxelColorUnit) uniform samplerBuffer colorData;
layout(location = kVoxelHasColorsLocation) uniform uint hasColors;
#endif

#include "voxel_fragment.glsl"
#include "voxel_triangle.glsl"

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

void main() {
  uint group = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  uint t = group * kResolveGroupSize + gl_LocalInvocationIndex;
  if (t >= triangleCount) return;

  vec3 g[3], vn[3];
  vec2 vt[3];
#if !defined(VOXGI_NO_TEXTURES) && !defined(VOXGI_NO_EMISSION)
  vec2 vt2[3];  // channel 1: the emissive texture's with kMaterialEmissiveUv2
  bool uv2 = (materials[materialIndex].flags & kMaterialEmissiveUv2) != 0u;
#endif
  vec4 vc[3];
  uint index[3];
  for (int i = 0; i < 3; ++i) {
    index[i] = texelFetch(indexData, int(firstIndex + 3u * t) + i).x;
    int v = int(index[i]);
    vec2 p = texelFetch(vertexData, 5 * v).xy;
    vec2 pn = texelFetch(vertexData, 5 * v + 1).xy;
    vec2 nn = texelFetch(vertexData, 5 * v + 2).xy;
    g[i] = voxelGridPosition(vec3(p, pn.x));
    vn[i] = vec3(pn.y, nn);
    vt[i] = texelFetch(vertexData, 5 * v + 3).xy;
#if !defined(VOXGI_NO_TEXTURES) && !defined(VOXGI_NO_EMISSION)
    vt2[i] = uv2 ? texelFetch(vertexData, 5 * v + 4).xy : vt[i];
#endif
#ifndef VOXGI_NO_COLORS
    vc[i] = hasColors != 0u ? texelFetch(colorData, v) : vec4(1.0);
#endif
  }
  vec3 n;
  int axis = voxelProjectionAxis(g[0], g[1], g[2], n);
  if (axis < 0) return;
  vec3 s0 = voxelSwizzle(g[0], axis), s1 = voxelSwizzle(g[1], axis), s2 = voxelSwizzle(g[2], axis);
  if (!voxelIsSmallTriangle(s0, s1, s2)) {  // to the raster
    // The group's command counts from the group's first index.
    uint at = firstIndex + 3u * kResolveGroupSize * group +
              atomicAdd(drawCommands[(firstCommand + group) * kDrawCommandWords], 3u);
    largeIndices[at] = index[0];
    largeIndices[at + 1u] = index[1];
    largeIndices[at + 2u] = index[2];
    return;
  }
#ifdef VOXGI_COUNT_SMALL
  atomicAdd(stats.smallTriangles, 1u);
#endif
  vec4 plane = voxelPlane(s0, voxelSwizzle(n, axis));
  vec2 depth = voxelDepthRange(s0, s1, s2);

  // Coverage in snapped sub-pixel units, relative to the lowest pixel corner. Each
  // edge a -> b of the counter-clockwise triangle has the function
  // E(p) = (b - a) x (p - a) = c + dx p.x + dy p.y, positive inside. A sample exactly
  // on an edge belongs to the triangle when the edge is a left edge (going down) or
  // a top edge (horizontal, going left), so a sample on an edge two triangles share
  // is counted once: E + bias > 0 with bias 1 on those edges. Small triangles keep
  // every term far below 2^31.
  vec2 lo = floor(min(s0.xy, min(s1.xy, s2.xy)));
  ivec2 hi = ivec2(floor(max(s0.xy, max(s1.xy, s2.xy))) - lo);
  int snap = int(voxel.slotInfo.z);
  ivec2 q[3] =
      ivec2[3](ivec2(round((s0.xy - lo) * float(snap))), ivec2(round((s1.xy - lo) * float(snap))),
               ivec2(round((s2.xy - lo) * float(snap))));
  int area = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[1].y - q[0].y) * (q[2].x - q[0].x);
  if (area == 0) return;  // no area once snapped: the rasterizer drops it too
  if (area < 0) {         // clockwise: swap two corners for the coverage test
    ivec2 t1 = q[1];
    q[1] = q[2];
    q[2] = t1;
  }
  ivec3 edgeC, edgeX, edgeY;  // per edge: E(p) = c + x p.x + y p.y (+ bias folded into c)
  for (int i = 0; i < 3; ++i) {
    ivec2 a = q[i], b = q[(i + 1) % 3];
    edgeX[i] = a.y - b.y;
    edgeY[i] = b.x - a.x;
    bool topLeft = b.y < a.y || (b.y == a.y && b.x < a.x);
    edgeC[i] = -(edgeX[i] * a.x + edgeY[i] * a.y) + (topLeft ? 1 : 0);
  }
  // The sample offsets' contributions, per sample and edge.
  ivec3 offset[4];
  for (int s = 0; s < 4; ++s) {
    vec2 sp = (s & 1) == 0 ? voxel.samplePositions[s >> 1].xy : voxel.samplePositions[s >> 1].zw;
    ivec2 o = ivec2(round(sp * float(snap)));
    offset[s] = edgeX * o.x + edgeY * o.y;
  }

  // Attributes: barycentric coordinates of the original corners, linear in (u, v).
  vec2 p0 = s0.xy - lo, e1 = s1.xy - s0.xy, e2 = s2.xy - s0.xy;
  float det = cross2(e1, e2);
  float inv = det != 0.0 ? 1.0 / det : 0.0;
  vec2 db1 = vec2(e2.y, -e2.x) * inv;  // d(b1)/d(u, v)
  vec2 db2 = vec2(-e1.y, e1.x) * inv;  // d(b2)/d(u, v)

  GpuMaterial m = materials[materialIndex];
#ifdef VOXGI_NO_EMISSION
  vec3 e = vec3(0.0);
#else
  vec3 e = m.emission * voxel.gridInfo.y;  // scaled so the scene's largest is 1
#endif
#ifndef VOXGI_NO_TEXTURES
  vec2 duvdx = (vt[1] - vt[0]) * db1.x + (vt[2] - vt[0]) * db2.x;
  vec2 duvdy = (vt[1] - vt[0]) * db1.y + (vt[2] - vt[0]) * db2.y;
#ifndef VOXGI_NO_EMISSION
  vec2 duv2dx = (vt2[1] - vt2[0]) * db1.x + (vt2[2] - vt2[0]) * db2.x;
  vec2 duv2dy = (vt2[1] - vt2[0]) * db1.y + (vt2[2] - vt2[0]) * db2.y;
#endif
#endif

  // First which pixels of the box any sample covers, one bit each, then one pass per
  // covered pixel: invocations of one SIMD batch step through their covered pixels
  // together instead of through their whole boxes.
  uvec2 covered = uvec2(0u);
  for (int py = 0; py <= hi.y; ++py) {
    for (int px = 0; px <= hi.x; ++px) {
      ivec3 e0 = edgeC + edgeX * (px * snap) + edgeY * (py * snap);  // at the pixel corner
      bool any_ = false;
      for (int s = 0; s < 4; ++s) any_ = any_ || all(greaterThan(e0 + offset[s], ivec3(0)));
      int bit = py * int(kSmallTriangleSpan) + px;
      if (any_) covered[bit >> 5] |= 1u << (bit & 31);
    }
  }
  while (covered != uvec2(0u)) {
    int word = covered.x != 0u ? 0 : 1;
    int bit = findLSB(covered[word]);
    covered[word] &= ~(1u << bit);
    bit += 32 * word;
    int px = bit % int(kSmallTriangleSpan), py = bit / int(kSmallTriangleSpan);
    ivec3 e0 = edgeC + edgeX * (px * snap) + edgeY * (py * snap);
    uint mask = 0u;
    vec2 at = vec2(0.0);  // sum, then centroid, of the covered samples
    for (int s = 0; s < 4; ++s) {
      if (all(greaterThan(e0 + offset[s], ivec3(0)))) {
        mask |= 1u << s;
        at += (s & 1) == 0 ? voxel.samplePositions[s >> 1].xy : voxel.samplePositions[s >> 1].zw;
      }
    }
    uint weight = uint(bitCount(mask));
    if (weight == 0u) continue;
    at = vec2(px, py) + (mask == 0xFu ? vec2(0.5) : at / float(weight));
    vec2 d = at - p0;
    float b1 = dot(d, db1), b2 = dot(d, db2);
    if (det == 0.0) b1 = b2 = 1.0 / 3.0;
    float b0 = 1.0 - b1 - b2;

    vec4 base = m.baseColor;
    vec3 emitted = e;
#ifndef VOXGI_NO_TEXTURES
    if ((m.flags & (kMaterialHasTexture | kMaterialHasEmissiveTexture)) != 0u) {
      vec2 uv = b0 * vt[0] + b1 * vt[1] + b2 * vt[2];
      if ((m.flags & kMaterialHasTexture) != 0u)
        base *= textureGrad(baseColorTexture, uv, duvdx, duvdy);
#ifndef VOXGI_NO_EMISSION
      if ((m.flags & kMaterialHasEmissiveTexture) != 0u) {
        if (uv2)
          emitted *=
              textureGrad(emissiveTexture, b0 * vt2[0] + b1 * vt2[1] + b2 * vt2[2], duv2dx, duv2dy)
                  .rgb;
        else
          emitted *= textureGrad(emissiveTexture, uv, duvdx, duvdy).rgb;
      }
#endif
    }
#endif
#ifndef VOXGI_NO_COLORS
    if (hasColors != 0u) base *= b0 * vc[0] + b1 * vc[1] + b2 * vc[2];
#endif
#ifndef VOXGI_NO_ALPHA
    if ((m.flags & (kMaterialAlphaMask | kMaterialAlphaBlend)) != 0u && base.a < m.alphaCutoff)
      continue;
#endif
    vec3 nn = normalize(b0 * vn[0] + b1 * vn[1] + b2 * vn[2]);
    if (any(isnan(nn))) nn = vec3(0.0);
    voxelAddFragment(ivec2(lo) + ivec2(px, py), axis, plane, depth, base.rgb, nn, emitted, weight);
  }
}
