// rtgi's interleave pattern (shaders/include/interleave_shared.h), the C++ build:
// each frame's packed dispatch reaches exactly the pixels whose turn it is, each
// once, and n consecutive frames reach every pixel once. The GLSL build agrees with
// it: tests/render/interleave_twin_gltest.cpp.
#include <gtest/gtest.h>

#include <vector>

#include "interleave_shared.h"

namespace voxgi::gpu {
namespace {

TEST(Interleave, RankAndCellAreInverse) {
  std::vector<int> seen(16, 0);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      const uint rank = interleaveRank(ivec2(x, y));
      ASSERT_LT(rank, 16u);
      ++seen[rank];
      EXPECT_EQ(interleaveCell(rank), uint(y * 4 + x));
      // The pattern repeats every 4 pixels.
      EXPECT_EQ(interleaveRank(ivec2(x + 8, y + 4)), rank);
    }
  for (int count : seen) EXPECT_EQ(count, 1);
}

TEST(Interleave, FirstFrameTracesEveryPixelUnlessSparse) {
  EXPECT_TRUE(interleaveEveryPixel(1u, 5u, true));
  EXPECT_TRUE(interleaveEveryPixel(4u, 0u, false));
  EXPECT_FALSE(interleaveEveryPixel(4u, 0u, true));
  EXPECT_FALSE(interleaveEveryPixel(4u, 1u, false));
}

// Image sizes with and without edge blocks cut by the image.
TEST(Interleave, PackedDispatchReachesTheTurnsPixelsOnce) {
  for (const ivec2 size : {ivec2(16, 8), ivec2(13, 7), ivec2(1, 1), ivec2(5, 9)}) {
    const uint w = uint(size.x), h = uint(size.y);
    for (uint n : {2u, 4u, 8u, 16u}) {
      std::vector<int> overTurns(w * h, 0);
      for (uint frame = 3u; frame < 3u + n; ++frame) {
        std::vector<int> reached(w * h, 0);
        const uint count = interleaveTraceCount(w, h, n, false);
        for (uint i = 0; i < count; ++i) {
          ivec2 px;
          if (interleavePixel(i, w, h, n, frame, false, px)) ++reached[uint(px.y) * w + uint(px.x)];
        }
        ivec2 px;
        EXPECT_FALSE(interleavePixel(count, w, h, n, frame, false, px));
        for (uint y = 0; y < h; ++y)
          for (uint x = 0; x < w; ++x) {
            const int r = reached[y * w + x];
            EXPECT_EQ(r, interleaveTraces(ivec2(int(x), int(y)), n, frame) ? 1 : 0)
                << w << "x" << h << " n " << n << " frame " << frame << " pixel " << x << "," << y;
            overTurns[y * w + x] += r;
          }
      }
      for (int r : overTurns) EXPECT_EQ(r, 1) << w << "x" << h << " n " << n;
    }
    // Every pixel: one invocation each, in rows.
    const uint count = interleaveTraceCount(w, h, 4u, true);
    EXPECT_EQ(count, w * h);
    for (uint i = 0; i < count; ++i) {
      ivec2 px;
      ASSERT_TRUE(interleavePixel(i, w, h, 4u, 0u, true, px));
      EXPECT_EQ(px, ivec2(int(i % w), int(i / w)));
    }
  }
}

}  // namespace
}  // namespace voxgi::gpu
