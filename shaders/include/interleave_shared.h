// rtgi's interleave pattern, written once in the common subset of GLSL and C++
// (shared_fn.h): which pixels trace new rays on a frame, and how the tracing stages
// pack them into their dispatch. RtgiPass sizes that dispatch with
// interleaveTraceCount; rtgi_common.glsl maps each invocation to its pixel with
// interleavePixel. Twin test: tests/render/interleave_twin_gltest.cpp; the pattern's
// properties: tests/render/interleave_test.cpp.
//
// With an interleave of n > 1 (1, 2, 4, 8 or 16) a pixel traces on every n-th frame
// only, the pixels of each 4x4 block taking turns in a 4x4 ordered (Bayer) order, so
// each frame's work is spread evenly over the image. The first frame of an
// accumulation traces every pixel, unless it starts sparse (kRtgiSparseStart).
#ifndef VOXGI_INTERLEAVE_SHARED_H
#define VOXGI_INTERLEAVE_SHARED_H

#include "shared_fn.h"

#ifdef __cplusplus
namespace voxgi::gpu {
#endif

// Whether every pixel traces on frame `frame` of an accumulation under interleave n.
VOXGI_FN bool interleaveEveryPixel(uint n, uint frame, bool sparseStart) {
  return n <= 1u || (frame == 0u && !sparseStart);
}

// The rank of pixel px in its 4x4 block's ordered pattern; by rows
// 0 8 2 10 / 12 4 14 6 / 3 11 1 9 / 15 7 13 5, packed 4 bits an entry.
VOXGI_FN uint interleaveRank(ivec2 px) {
  uint k = (uint(px.y) & 3u) * 4u + (uint(px.x) & 3u);
  return ((k < 8u ? 0x6e4ca280u : 0x5d7f91b3u) >> (4u * (k & 7u))) & 15u;
}

// The inverse of interleaveRank: rank -> cell of the 4x4 block (x in bits 0-1, y in
// bits 2-3).
VOXGI_FN uint interleaveCell(uint rank) {
  return ((rank < 8u ? 0xd7f582a0u : 0xc6e493b1u) >> (4u * (rank & 7u))) & 15u;
}

// The rank of frame `frame`'s turn: the pixels of rank r with (r + frame) % n == 0
// trace.
VOXGI_FN uint interleaveTurn(uint n, uint frame) { return (n - (frame & (n - 1u))) & (n - 1u); }

// Whether pixel px has its turn on frame `frame` (interleave n > 1).
VOXGI_FN bool interleaveTraces(ivec2 px, uint n, uint frame) {
  return ((interleaveRank(px) + frame) & (n - 1u)) == 0u;
}

// How many invocations the tracing stages run for a w x h image: one per pixel, or
// with interleaving 16 / n per 4x4 block (blocks cut by the image's edge included).
VOXGI_FN uint interleaveTraceCount(uint w, uint h, uint n, bool everyPixel) {
  return everyPixel ? w * h : ((w + 3u) / 4u) * ((h + 3u) / 4u) * (16u / n);
}

// The pixel that invocation i traces; false past the last pixel, or on a cell of an
// edge block outside the image. Pixels come block by block, so neighbouring
// invocations trace neighbouring pixels.
VOXGI_FN bool interleavePixel(uint i, uint w, uint h, uint n, uint frame, bool everyPixel,
                              VOXGI_OUT(ivec2) px) {
  if (everyPixel) {
    px = ivec2(int(i % w), int(i / w));
    return i < w * h;
  }
  uint perBlock = 16u / n;
  uint block = i / perBlock;
  uint blocksX = (w + 3u) / 4u;
  uint cell = interleaveCell(interleaveTurn(n, frame) + (i % perBlock) * n);
  px = ivec2(int((block % blocksX) * 4u + (cell & 3u)), int((block / blocksX) * 4u + (cell >> 2u)));
  return block < blocksX * ((h + 3u) / 4u) && px.x < int(w) && px.y < int(h);
}

#ifdef __cplusplus
}  // namespace voxgi::gpu
#endif

#endif  // VOXGI_INTERLEAVE_SHARED_H
