// The normal-map functions shared by the shaders and the CPU path tracer
// (shaders/include/normal_map_shared.h), in their C++ build, on known answers and
// random inputs: the perturbation, the back-facing rule and rtgi's packed normal.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "normal_map_shared.h"

namespace voxgi::gpu {
namespace {

glm::vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  for (;;) {
    const glm::vec3 v(g(rng), g(rng), g(rng));
    if (glm::length(v) > 1e-3f) return glm::normalize(v);
  }
}

TEST(NormalMapShared, FlatTexelKeepsTheNormal) {
  const glm::vec3 n = glm::normalize(glm::vec3(0.2f, -0.3f, 1.0f));
  const glm::vec3 m = perturbNormal(n, glm::vec4(1, 0, 0, 1), glm::vec3(0.5f, 0.5f, 1.0f), 1.0f);
  EXPECT_NEAR(glm::dot(m, n), 1.0f, 1e-6f);
}

TEST(NormalMapShared, TiltInTheTangentFrame) {
  // +x in tangent space is the tangent; +y the bitangent w * cross(n, t).
  const glm::vec3 n(0, 0, 1);
  const float s = std::sqrt(0.5f);
  const glm::vec3 tx(0.5f + 0.5f * s, 0.5f, 0.5f + 0.5f * s);
  const glm::vec3 ty(0.5f, 0.5f + 0.5f * s, 0.5f + 0.5f * s);
  const glm::vec3 a = perturbNormal(n, glm::vec4(1, 0, 0, 1), tx, 1.0f);
  EXPECT_NEAR(a.x, s, 1e-5f);
  EXPECT_NEAR(a.z, s, 1e-5f);
  const glm::vec3 b = perturbNormal(n, glm::vec4(1, 0, 0, 1), ty, 1.0f);
  EXPECT_NEAR(b.y, s, 1e-5f);
  const glm::vec3 c = perturbNormal(n, glm::vec4(1, 0, 0, -1), ty, 1.0f);  // mirrored frame
  EXPECT_NEAR(c.y, -s, 1e-5f);
  // scale 0 flattens the map; a tangent along n gives n back.
  EXPECT_NEAR(glm::dot(perturbNormal(n, glm::vec4(1, 0, 0, 1), tx, 0.0f), n), 1.0f, 1e-6f);
  EXPECT_EQ(perturbNormal(n, glm::vec4(0, 0, 1, 1), tx, 1.0f), n);
}

TEST(NormalMapShared, BentNormalKeepsTheViewerAbove) {
  std::mt19937 rng(7);
  for (int i = 0; i < 100000; ++i) {
    const glm::vec3 ns = randomUnit(rng), wo = randomUnit(rng);
    const glm::vec3 b = bendShadingNormal(ns, wo);
    ASSERT_TRUE(std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z));
    EXPECT_NEAR(glm::length(b), 1.0f, 1e-4f);
    EXPECT_GE(glm::dot(b, wo), 0.5f * kMinShadingCos);
    if (glm::dot(ns, wo) >= kMinShadingCos) {
      EXPECT_EQ(b, ns);  // untouched when visible
    }
  }
}

TEST(NormalMapShared, PackedSurfaceNormalWithinFourDegrees) {
  std::mt19937 rng(11);
  for (int i = 0; i < 100000; ++i) {
    const glm::vec3 n = randomUnit(rng);
    const float code = packSurfaceNormal(n);
    ASSERT_NE(code, 0.0f);
    // What a half float keeps: integers up to 2048 exactly.
    ASSERT_EQ(code, std::round(code));
    ASSERT_LE(std::abs(code), 2048.0f);
    EXPECT_GT(glm::dot(unpackSurfaceNormal(code), n), std::cos(glm::radians(4.0f))) << i;
  }
}

}  // namespace
}  // namespace voxgi::gpu
