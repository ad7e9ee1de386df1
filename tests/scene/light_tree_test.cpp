// The light tree (scene::buildLightTree, light_tree_shared.h's traversal compiled as
// C++): its shape, that every emitter which lights a point can be drawn there (so
// the estimate stays unbiased), that the probabilities it reports are those of its
// walk, and that it draws a sphere lamp's clusters with less variance than drawing
// by power does.
#include "scene/light_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "scene/emitters.h"

namespace voxgi::scene {
namespace {

constexpr float kPi = 3.14159265358979f;

// A lamp like dark_plane's: clusters over a sphere, facing out (Fibonacci points).
std::vector<Emitter> sphereLamp(glm::vec3 centre, float radius, int count) {
  std::vector<Emitter> out;
  const float area = 4.0f * kPi * radius * radius / static_cast<float>(count);
  for (int i = 0; i < count; ++i) {
    const float z = 1.0f - 2.0f * (static_cast<float>(i) + 0.5f) / static_cast<float>(count);
    const float phi = 2.39996323f * static_cast<float>(i);
    const float r = std::sqrt(1.0f - z * z);
    Emitter e;
    e.kind = Emitter::Kind::kCluster;
    e.normal = glm::vec3(r * std::cos(phi), z, r * std::sin(phi));
    e.v0 = centre + radius * e.normal;
    e.area = area;
    e.radiance = glm::vec3(8.0f, 7.0f, 6.0f);
    out.push_back(e);
  }
  return out;
}

Emitter triangle(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, bool twoSided, glm::vec3 radiance) {
  Emitter e;
  e.v0 = v0;
  e.v1 = v1;
  e.v2 = v2;
  e.normal = glm::normalize(glm::cross(v1 - v0, v2 - v0));
  e.area = 0.5f * glm::length(glm::cross(v1 - v0, v2 - v0));
  e.radiance = radiance;
  e.twoSided = twoSided;
  return e;
}

// More emitters than kLightTreeLeafDraw, so that the walk takes binary steps first.
std::vector<Emitter> mixedScene() {
  auto e = sphereLamp(glm::vec3(0.2f, 1.2f, -0.1f), 0.15f, 300);
  e.push_back(triangle({-0.5f, 1.9f, -0.5f}, {0.5f, 1.9f, -0.5f}, {0.0f, 1.9f, 0.5f}, false,
                       glm::vec3(3.0f)));
  e.push_back(triangle({0.9f, 0.2f, 0.0f}, {0.9f, 0.6f, 0.3f}, {0.9f, 0.2f, 0.4f}, true,
                       glm::vec3(1.0f, 0.2f, 0.2f)));
  e.push_back(triangle({-0.9f, 0.2f, 0.0f}, {-0.9f, 0.6f, 0.3f}, {-0.9f, 0.2f, 0.4f}, false,
                       glm::vec3(0.0f)));  // no power
  return e;
}

size_t index(float f) {
  return static_cast<size_t>(f);
}

// Every emitter's probability of being drawn at (p, n), the walk's branches all taken
// down to nodes of at most leafDraw emitters.
void leafProbabilities(const std::vector<gpu::GpuLightNode>& nodes, size_t at, double pmf,
                       glm::vec3 p, glm::vec3 n, std::vector<double>& out,
                       float leafDraw = gpu::kLightTreeLeafDraw) {
  const gpu::GpuLightNode& node = nodes[at];
  if (node.info.w <= leafDraw) {
    double total = 0.0;
    for (size_t k = index(node.info.z); k < index(node.info.z + node.info.w); ++k)
      total += gpu::lightNodeImportance(nodes[k], p, n);
    if (!(total > 0.0)) return;
    for (size_t k = index(node.info.z); k < index(node.info.z + node.info.w); ++k)
      out[index(nodes[k].info.y)] += pmf * gpu::lightNodeImportance(nodes[k], p, n) / total;
    return;
  }
  const size_t first = index(node.info.y);
  const double il = gpu::lightNodeImportance(nodes[first], p, n);
  const double ir = gpu::lightNodeImportance(nodes[first + 1], p, n);
  if (!(il + ir > 0.0)) return;
  leafProbabilities(nodes, first, pmf * il / (il + ir), p, n, out, leafDraw);
  leafProbabilities(nodes, first + 1, pmf * ir / (il + ir), p, n, out, leafDraw);
}

TEST(LightTree, HoldsEveryEmitterOnceWithItsPower) {
  const auto emitters = packEmitters(mixedScene());
  const auto nodes = buildLightTree(emitters);
  const size_t n = emitters.size();
  ASSERT_EQ(nodes.size(), 3 * n - 1);
  // The leaf section is the emitters, each once.
  std::vector<int> seen(n, 0);
  for (size_t k = 2 * n - 1; k < nodes.size(); ++k) {
    EXPECT_EQ(nodes[k].info.w, 1.0f);
    EXPECT_EQ(index(nodes[k].info.z), k);
    ++seen[index(nodes[k].info.y)];
  }
  for (size_t i = 0; i < n; ++i) EXPECT_EQ(seen[i], 1) << "emitter " << i;
  // Each inner node: its leaves are its children's, its power their sum, and its
  // sphere and cone hold every leaf's.
  for (size_t k = 0; k < 2 * n - 1; ++k) {
    const auto& node = nodes[k];
    if (node.info.w == 1.0f) {
      EXPECT_EQ(nodes[index(node.info.z)].info.y, node.info.y);
      continue;
    }
    const auto& l = nodes[index(node.info.y)];
    const auto& r = nodes[index(node.info.y) + 1];
    EXPECT_EQ(l.info.z, node.info.z);
    EXPECT_EQ(r.info.z, node.info.z + l.info.w);
    EXPECT_EQ(l.info.w + r.info.w, node.info.w);
    EXPECT_NEAR(l.info.x + r.info.x, node.info.x, 1e-5 * node.info.x);
    for (size_t j = index(node.info.z); j < index(node.info.z + node.info.w); ++j) {
      const auto& leaf = nodes[j];
      EXPECT_LE(glm::length(glm::vec3(leaf.sphere) - glm::vec3(node.sphere)) + leaf.sphere.w,
                node.sphere.w);
      const glm::dvec3 a(leaf.cone), b(node.cone);
      const double angle = 2.0 * std::asin(std::min(0.5 * glm::length(a - b), 1.0));
      if (node.cone.w > -1.0f) {
        EXPECT_LE(angle + std::acos(double(leaf.cone.w)), std::acos(double(node.cone.w)));
      }
    }
  }
  double power = 0.0;
  for (const auto& e : emitters) power += emitterPower(e);
  EXPECT_NEAR(nodes[0].info.x, power, 1e-4 * power);
  EXPECT_TRUE(buildLightTree({}).empty());
}

// Checks the walk down to nodes of at most leafDraw emitters at 1000 points: every
// emitter that lights the point can be drawn, and the walk's pmf is its probability.
// Returns the mean share of the draws lost where bounds were loose.
double checkWalk(float leafDraw) {
  const auto scene = mixedScene();
  const auto emitters = packEmitters(scene);
  const auto nodes = buildLightTree(emitters);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int lit = 0;
  double lost = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const glm::vec3 p(u(rng), 1.0f + u(rng), u(rng));
    glm::vec3 n(u(rng), u(rng), u(rng));
    if (glm::length(n) < 0.1f) continue;
    n = glm::normalize(n);
    std::vector<double> pmf(emitters.size(), 0.0);
    leafProbabilities(nodes, 0, 1.0, p, n, pmf, leafDraw);
    double sum = 0.0;
    bool any = false;
    for (size_t i = 0; i < scene.size(); ++i) {
      sum += pmf[i];
      // Unbiased: what lights the point can be drawn.
      if (emitterIrradianceFactor(scene[i], p, n) > 0.0f && emitterPower(emitters[i]) > 0.0) {
        EXPECT_GT(pmf[i], 0.0) << "emitter " << i << " at " << p.x << "," << p.y << "," << p.z;
        ++lit;
        any = true;
      }
    }
    // A walk may end where the bounds of a node were loose and neither child can
    // contribute: that share of the draws is lost (drawn as no emitter).
    EXPECT_LE(sum, 1.0 + 1e-5);
    if (any) lost += 1.0 - sum;
    // The walk's answer and its probability.
    for (float v : {0.03f, 0.41f, 0.77f, 0.9999f}) {
      float drawn = 0.0f;
      const int i =
          gpu::pickLightTree(nodes.data(), v, static_cast<uint32_t>(rng()), p, n, leafDraw, drawn);
      if (i < 0) {
        EXPECT_EQ(drawn, 0.0f);
        continue;
      }
      EXPECT_GT(pmf[static_cast<size_t>(i)], 0.0);
      EXPECT_NEAR(drawn, pmf[static_cast<size_t>(i)], 1e-4 * pmf[static_cast<size_t>(i)] + 1e-7);
    }
  }
  EXPECT_GT(lit, 30000);  // the test saw many lit pairs
  return lost / 1000.0;
}

TEST(LightTree, DrawsEveryEmitterThatLightsThePointWithTheWalksProbability) {
  EXPECT_LT(checkWalk(gpu::kLightTreeLeafDraw), 0.2);  // measured 0.128, most of it near the lamp
}

TEST(LightTree, WalksDownToSmallNodesWithTheSameGuarantees) {
  // As at rtgi's indirect hits (RtgiPass::Settings::leafDrawAtHits): more binary steps.
  const double lost = checkWalk(8.0f);
  std::printf("lost share at 8 emitters a draw: %.3f\n", lost);
  EXPECT_LT(lost, 0.2);  // measured 0.156
}

// The variance of the one-sample estimate sum f_i / p_i for probabilities p.
double variance(const std::vector<double>& f, const std::vector<double>& p) {
  double mean = 0.0, second = 0.0;
  for (size_t i = 0; i < f.size(); ++i) {
    mean += f[i];
    if (f[i] > 0.0) second += f[i] * f[i] / p[i];
  }
  return second - mean * mean;
}

// What drawing from the tree leaves of drawing by power's variance, summed over a row
// of points on the floor under a sphere lamp of `clusters` clusters.
double varianceRatio(int clusters, float leafDraw = gpu::kLightTreeLeafDraw) {
  const auto scene = sphereLamp(glm::vec3(0.0f, 1.0f, 0.0f), 0.1f, clusters);
  const auto emitters = packEmitters(scene);
  const auto nodes = buildLightTree(emitters);
  const auto cdf = emitterPowerCdf(emitters);
  double byTree = 0.0, byPower = 0.0;
  for (float x : {-1.5f, -0.6f, 0.0f, 0.3f, 1.2f}) {
    const glm::vec3 p(x, 0.0f, 0.2f * x), n(0.0f, 1.0f, 0.0f);
    std::vector<double> f, tree(emitters.size(), 0.0), power;
    for (size_t i = 0; i < scene.size(); ++i) {
      f.push_back(emitterIrradianceFactor(scene[i], p, n));
      power.push_back(cdf[i] - (i > 0 ? cdf[i - 1] : 0.0f));
    }
    leafProbabilities(nodes, 0, 1.0, p, n, tree, leafDraw);
    byTree += variance(f, tree);
    byPower += variance(f, power);
  }
  return byTree / byPower;
}

TEST(LightTree, DrawsASphereLampWithLessVarianceThanPower) {
  // As in dark_plane (96 clusters): drawing by power spends half its draws on the
  // clusters that face away. Within kLightTreeLeafDraw emitters the draw is in
  // proportion to each one's bound, which for a cluster is all but its contribution.
  EXPECT_LT(varianceRatio(96), 0.01);  // measured 0.0011
  // More than kLightTreeLeafDraw: binary steps first, whose bounds are looser.
  EXPECT_LT(varianceRatio(1000), 0.5);  // measured 0.254
  // The walk down to nodes of 16 clusters, as at rtgi's indirect hits
  // (RtgiPass::Settings::leafDrawAtHits): looser than the leaves' bounds, still far
  // better than power.
  EXPECT_LT(varianceRatio(96, 16.0f), 0.25);  // measured 0.166 (to 8 clusters: 0.205)
}

// A hall's lights: a 16 x 4 m skylight panel (two triangles) 7.5 m over the floor, and
// 24 small sphere lamps 2.6 m up along two rows; the relative variance of the
// one-sample estimate drawn from the tree, summed over points on the floor and on
// upright faces, some beside a lamp.
double hallRelativeVariance() {
  std::vector<Emitter> scene;
  const glm::vec3 sky(4.0f, 4.2f, 4.6f);
  scene.push_back(
      triangle({-8.0f, 7.5f, -2.0f}, {8.0f, 7.5f, -2.0f}, {8.0f, 7.5f, 2.0f}, false, sky));
  scene.push_back(
      triangle({-8.0f, 7.5f, -2.0f}, {8.0f, 7.5f, 2.0f}, {-8.0f, 7.5f, 2.0f}, false, sky));
  EXPECT_LT(scene[0].normal.y, -0.99f);  // facing down
  EXPECT_LT(scene[1].normal.y, -0.99f);
  for (int i = 0; i < 24; ++i) {
    const float x = -10.0f + 20.0f * static_cast<float>(i % 12) / 11.0f;
    const float z = i < 12 ? -3.0f : 3.0f;
    for (Emitter e : sphereLamp(glm::vec3(x, 2.6f, z), 0.045f, 60)) {
      e.radiance = glm::vec3(160.0f, 130.0f, 90.0f);
      scene.push_back(e);
    }
  }
  const auto emitters = packEmitters(scene);
  const auto nodes = buildLightTree(emitters);
  double sum = 0.0;
  const glm::vec3 up(0.0f, 1.0f, 0.0f), side(0.0f, 0.0f, 1.0f);
  for (const auto& [p, n] : {std::pair{glm::vec3(0.0f, 0.0f, 0.0f), up},
                             {glm::vec3(-5.0f, 0.0f, -3.0f), up},
                             {glm::vec3(3.6f, 0.0f, 2.5f), up},
                             {glm::vec3(-1.0f, 2.0f, -3.4f), side},
                             {glm::vec3(6.0f, 3.0f, 2.4f), -side},
                             {glm::vec3(0.0f, 1.0f, -1.5f), side}}) {
    std::vector<double> f, tree(emitters.size(), 0.0);
    double total = 0.0;
    for (const Emitter& e : scene) {
      const double lum = 0.2126 * e.radiance.r + 0.7152 * e.radiance.g + 0.0722 * e.radiance.b;
      f.push_back(lum * emitterIrradianceFactor(e, p, n));
      total += f.back();
    }
    leafProbabilities(nodes, 0, 1.0, p, n, tree);
    sum += variance(f, tree) / (total * total);
  }
  return sum;
}

TEST(LightTree, DrawsSmallLampsBesideALargePanelInProportionToTheirLight) {
  // A point inside a node's bounding sphere once counted the node's whole power: the
  // panel's triangles, whose spheres reach the floor, outweighed the lamps tens of
  // times over, and a lamp's rare draw was a firefly.
  // Measured 5.37 (no randomness: the walk's probabilities are summed exactly); 61.8
  // with the whole power inside a sphere.
  EXPECT_LT(hallRelativeVariance(), 8.0);
}

// A node's importance for a region of receivers (lightNodeRegionImportance, what
// rtgi's light tiles weigh emitters by) bounds its importance at every point and
// normal of the region: an emitter that can light one pixel of a tile keeps a
// probability above 0 in the tile, and the draw stays unbiased. Every node of a
// tree over mixedScene(), regions of radius 0 to 0.6 whose normals spread by up to
// 90 degrees, points and normals drawn inside them.
TEST(LightTree, ARegionsImportanceBoundsItsPoints) {
  const auto emitters = packEmitters(mixedScene());
  const auto nodes = buildLightTree(emitters);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  auto unit = [&] {
    for (;;) {
      const glm::vec3 v(u(rng), u(rng), u(rng));
      if (glm::length(v) > 0.1f && glm::length(v) <= 1.0f) return glm::normalize(v);
    }
  };
  int compared = 0, positive = 0;
  for (int region = 0; region < 300; ++region) {
    const glm::vec3 c(1.5f * u(rng), 1.0f + 1.5f * u(rng), 1.5f * u(rng));
    const float radius = 0.6f * u01(rng) * u01(rng);
    const glm::vec3 axis = unit();
    const float cosN = std::cos(1.5707963f * u01(rng) * u01(rng));
    for (int k = 0; k < 20; ++k) {
      // A point inside the region's sphere and a normal inside its cone.
      const glm::vec3 p = c + unit() * radius * std::cbrt(u01(rng));
      glm::vec3 n = unit();
      if (glm::dot(n, axis) < cosN) {
        const glm::vec3 side = glm::normalize(n - glm::dot(n, axis) * axis);
        const float cosA = cosN + (1.0f - cosN) * u01(rng);
        n = cosA * axis + std::sqrt(std::max(1.0f - cosA * cosA, 0.0f)) * side;
      }
      for (size_t i = 0; i < nodes.size(); i += 7) {
        const float atPoint = gpu::lightNodeImportance(nodes[i], p, n);
        const float atRegion = gpu::lightNodeRegionImportance(nodes[i], c, radius, axis, cosN);
        ++compared;
        if (atPoint > 0.0f) ++positive;
        EXPECT_GE(atRegion, 0.999f * atPoint)
            << "node " << i << ", region radius " << radius << ", cos " << cosN;
      }
    }
  }
  EXPECT_GT(positive, compared / 4);  // the test saw many lit pairs
  // A region of one point and one normal is that point.
  for (size_t i = 0; i < nodes.size(); i += 13) {
    const glm::vec3 p(0.3f, 0.4f, -0.2f), n = glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f));
    EXPECT_NEAR(gpu::lightNodeRegionImportance(nodes[i], p, 0.0f, n, 1.0f),
                gpu::lightNodeImportance(nodes[i], p, n),
                1e-5f * gpu::lightNodeImportance(nodes[i], p, n));
  }
}

}  // namespace
}  // namespace voxgi::scene
