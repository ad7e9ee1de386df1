// Directions uniform in the solid angle of a triangle (sampleSphericalTriangle in
// shaders/include/sampling_shared.h, which rtgi's direct light draws from), in its
// C++ build: every direction lands on the triangle, each part of the triangle gets
// its share of the directions, and the mean cosine over them is the closed-form
// irradiance factor (emitter_shared.h) that the shaders' exact emitter sums use.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "emitter_shared.h"
#include "sampling_shared.h"

namespace voxgi::gpu {
namespace {

struct Triangle {
  vec3 a, b, c;
};

// A triangle seen from the origin under roughly `size` radians, at a random place.
Triangle randomTriangle(std::mt19937& rng, float size) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::normal_distribution<float> g;
  const vec3 centre = glm::normalize(vec3(g(rng), g(rng), g(rng))) * 2.0f;
  Triangle t;
  for (vec3* v : {&t.a, &t.b, &t.c}) *v = centre + 2.0f * size * vec3(u(rng), u(rng), u(rng));
  return t;
}

// Where the ray from the origin along d meets the triangle's plane, and whether
// that point lies inside it (barycentrics within `slack` of [0, 1]).
bool rayHits(const Triangle& t, vec3 d, float slack) {
  const vec3 e1 = t.b - t.a, e2 = t.c - t.a;
  const vec3 pv = cross(d, e2);
  const float det = dot(e1, pv);
  if (std::abs(det) < 1e-12f) return false;
  const vec3 tv = -t.a;
  const float bu = dot(tv, pv) / det;
  const vec3 qv = cross(tv, e1);
  const float bv = dot(d, qv) / det;
  const float dist = dot(e2, qv) / det;
  return dist > 0.0f && bu >= -slack && bv >= -slack && bu + bv <= 1.0f + slack;
}

float solidAngle(const Triangle& t) {
  return sphericalTriangleArea(normalize(t.a), normalize(t.b), normalize(t.c));
}

struct Sizes : testing::TestWithParam<float> {};

// Sizes from just above kMinSphericalTriangle to a triangle filling much of the
// hemisphere.
INSTANTIATE_TEST_SUITE_P(SphericalTriangle, Sizes, testing::Values(0.15f, 0.3f, 0.6f, 0.9f));

TEST_P(Sizes, EveryPartGetsItsShareAndEveryDirectionLandsOnTheTriangle) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  constexpr int kTriangles = 40;
  constexpr int kSamples = 20000;
  int tested = 0;
  for (int k = 0; k < kTriangles; ++k) {
    const Triangle t = randomTriangle(rng, GetParam());
    const float area = solidAngle(t);
    if (!(area > kMinSphericalTriangle)) continue;
    ++tested;
    // The four triangles of the midpoint subdivision, by their solid angle.
    const vec3 ab = 0.5f * (t.a + t.b), bc = 0.5f * (t.b + t.c), ca = 0.5f * (t.c + t.a);
    const std::array<Triangle, 4> parts = {Triangle{t.a, ab, ca}, Triangle{ab, t.b, bc},
                                           Triangle{ca, bc, t.c}, Triangle{ab, bc, ca}};
    std::array<int, 4> counts{};
    int missed = 0;
    for (int i = 0; i < kSamples; ++i) {
      const vec3 d = sampleSphericalTriangle(normalize(t.a), normalize(t.b), normalize(t.c), area,
                                             vec2(u01(rng), u01(rng)));
      ASSERT_NEAR(length(d), 1.0f, 1e-4f);
      if (!rayHits(t, d, 1e-4f)) ++missed;
      for (int p = 0; p < 4; ++p)
        if (rayHits(parts[p], d, 0.0f)) {
          ++counts[p];
          break;
        }
    }
    EXPECT_EQ(missed, 0) << "triangle " << k << ", solid angle " << area;
    for (int p = 0; p < 4; ++p) {
      // Binomial: the count is within 5 standard deviations of its share.
      const double share = solidAngle(parts[p]) / area;
      const double expected = share * kSamples;
      const double sigma = std::sqrt(kSamples * share * (1.0 - share));
      EXPECT_NEAR(counts[p], expected, 5.0 * sigma + 2.0)
          << "triangle " << k << " part " << p << ", solid angle " << area;
    }
  }
  EXPECT_GE(tested, kTriangles / 4);
}

TEST_P(Sizes, MeanCosineIsTheClosedFormIrradiance) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  constexpr int kSamples = 50000;
  for (int k = 0; k < 20; ++k) {
    const Triangle t = randomTriangle(rng, GetParam());
    const float area = solidAngle(t);
    if (!(area > kMinSphericalTriangle)) continue;
    // A receiver at the origin facing the triangle's centre, so it is wholly above
    // the horizon (the closed form clips what is below).
    const vec3 centre = (t.a + t.b + t.c) / 3.0f;
    vec3 n = normalize(centre);
    bool above = dot(n, normalize(t.a)) > 0.0f && dot(n, normalize(t.b)) > 0.0f &&
                 dot(n, normalize(t.c)) > 0.0f;
    if (!above) continue;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < kSamples; ++i) {
      const vec3 d = sampleSphericalTriangle(normalize(t.a), normalize(t.b), normalize(t.c), area,
                                             vec2(u01(rng), u01(rng)));
      const double f = std::max(0.0f, dot(d, n)) * area;  // estimate with pdf 1/area
      sum += f;
      sum2 += f * f;
    }
    const double mean = sum / kSamples;
    const double stderr_ = std::sqrt(std::max(0.0, sum2 / kSamples - mean * mean) / kSamples);
    const double exact = triangleEmitterFactor(t.a, t.b, t.c, true, vec3(0.0f), n);
    EXPECT_NEAR(mean, exact, 5.0 * stderr_ + 1e-5 * exact) << "triangle " << k;
  }
}

// A receiver's normal at random, near the horizon of direction `towards` (the
// triangle's centre), so that the horizon cuts many of the triangles.
vec3 grazingNormal(std::mt19937& rng, vec3 towards) {
  std::normal_distribution<float> g;
  const vec3 w = glm::normalize(towards);
  const vec3 r(g(rng), g(rng), g(rng));
  return glm::normalize(r - w * dot(r, w) + w * (0.3f * g(rng)));
}

// The cosine-weighted draw over the part of a triangle above the receiver's horizon
// (sampleClippedTriangle, which rtgi's emitter light draws from): the mean of
// cos / pdf over its directions is the closed-form irradiance factor of the clipped
// triangle, each direction lands on the triangle and above the horizon, and its
// estimate varies far less than a uniform draw over the whole triangle's.
TEST_P(Sizes, ClippedCosineDrawGivesTheIrradianceWithLessNoise) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  constexpr int kSamples = 20000;
  int straddling = 0;
  double uniformVariance = 0.0, cosineVariance = 0.0;
  for (int k = 0; k < 120; ++k) {
    const Triangle t = randomTriangle(rng, GetParam());
    const float area = solidAngle(t);
    if (!(area > kMinSphericalTriangle)) continue;
    const vec3 n = grazingNormal(rng, t.a + t.b + t.c);
    const double exact = triangleEmitterFactor(t.a, t.b, t.c, true, vec3(0.0f), n);
    const int below =
        int(dot(t.a, n) <= 0.0f) + int(dot(t.b, n) <= 0.0f) + int(dot(t.c, n) <= 0.0f);
    double sum = 0.0, sum2 = 0.0, uSum2 = 0.0;
    int offTriangle = 0, belowHorizon = 0;
    for (int i = 0; i < kSamples; ++i) {
      vec3 d;
      const float pdf = sampleClippedTriangle(t.a, t.b, t.c, n, vec2(u01(rng), u01(rng)), d);
      double f = 0.0;
      if (pdf > 0.0f) {
        if (!rayHits(t, d, 2e-3f)) ++offTriangle;
        if (dot(d, n) < -1e-3f) ++belowHorizon;
        f = std::max(0.0f, dot(d, n)) / pdf;
      }
      sum += f;
      sum2 += f * f;
      const vec3 du = sampleSphericalTriangle(normalize(t.a), normalize(t.b), normalize(t.c), area,
                                              vec2(u01(rng), u01(rng)));
      const double fu = std::max(0.0f, dot(du, n)) * area;
      uSum2 += fu * fu;
    }
    const double mean = sum / kSamples;
    const double var = std::max(0.0, sum2 / kSamples - mean * mean);
    EXPECT_NEAR(mean, exact, 5.0 * std::sqrt(var / kSamples) + 1e-4 * exact + 1e-6)
        << "triangle " << k << ", corners below the horizon " << below;
    EXPECT_LE(offTriangle, kSamples / 1000) << "triangle " << k;
    EXPECT_EQ(belowHorizon, 0) << "triangle " << k;
    if (below == 0 || below == 3) continue;
    ++straddling;
    uniformVariance += uSum2 / kSamples - exact * exact;
    cosineVariance += var;
  }
  ASSERT_GE(straddling, 10);
  // Measured, summed over the triangles the horizon cuts: 0.059, 0.066, 0.054 and
  // 0.034 of the uniform draw's variance at the four sizes; clipped but drawn
  // uniformly over the clipped part (no warp), 0.48, 0.54, 0.45 and 0.27.
  EXPECT_LT(cosineVariance, 0.15 * uniformVariance);
}

}  // namespace
}  // namespace voxgi::gpu
