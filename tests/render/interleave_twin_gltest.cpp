// rtgi's interleave pattern (interleave_shared.h) agrees between its GLSL build (run
// by llvmpipe) and its C++ build, which RtgiPass uses to size the tracing stages'
// dispatch and tests/render/interleave_test.cpp checks: bit for bit, on random
// invocations, image sizes, interleaves, frames and sparse starts.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "interleave_shared.h"
#include "support/gl_fixture.h"
#include "support/twin_shader.h"

namespace voxgi::test {
namespace {

TEST_F(GlTest, InterleaveAgreesBetweenGlslAndCpp) {
  constexpr int kCases = 4096;
  std::mt19937 rng(23);
  std::vector<glm::uvec4> inputs;
  for (int c = 0; c < kCases; ++c) {
    const uint32_t w = 1u + rng() % 300u, h = 1u + rng() % 200u;
    const uint32_t n = 1u << (rng() % 5u);
    const uint32_t frame = c % 8 == 0 ? 0u : rng() % 1000u;
    const uint32_t sparse = rng() % 2u;
    // Invocations up to a little past the last one the dispatch needs.
    const bool every = gpu::interleaveEveryPixel(n, frame, sparse != 0u);
    const uint32_t i = rng() % (gpu::interleaveTraceCount(w, h, n, every) + 16u);
    inputs.push_back(glm::uvec4(i, w, h, n | (frame << 8u) | (sparse << 31u)));
  }

  const std::vector<glm::uvec4> gpuOut =
      runTwinShader<glm::uvec4>("interleave_twin.comp", {twinInput(inputs)}, kCases);

  // The C++ build of interleave_twin.comp's main.
  int same = 0, traced = 0;
  for (int c = 0; c < kCases; ++c) {
    const glm::uvec4 a = inputs[static_cast<size_t>(c)];
    const uint32_t n = a.w & 255u, frame = (a.w >> 8u) & 0xffffu;
    const bool every = gpu::interleaveEveryPixel(n, frame, (a.w >> 31u) != 0u);
    glm::ivec2 px(-1);
    const bool ok = gpu::interleavePixel(a.x, a.y, a.z, n, frame, every, px);
    const glm::ivec2 q(static_cast<int>(a.x % 61u), static_cast<int>(a.x / 61u));
    const glm::uvec4 r((ok ? 1u : 0u) | (every ? 2u : 0u) |
                           (gpu::interleaveTraces(q, n, frame) ? 4u : 0u) |
                           (gpu::interleaveTurn(n, frame) << 3u) | (gpu::interleaveRank(q) << 8u) |
                           (gpu::interleaveCell(a.x & 15u) << 12u),
                       static_cast<uint32_t>(px.x), static_cast<uint32_t>(px.y),
                       gpu::interleaveTraceCount(a.y, a.z, n, every));
    if (ok) ++traced;
    if (r == gpuOut[static_cast<size_t>(c)]) ++same;
  }
  EXPECT_GT(traced, kCases / 2);  // most invocations reach a pixel
  EXPECT_EQ(same, kCases) << "integer code must agree bit for bit";
}

}  // namespace
}  // namespace voxgi::test
