// The path tracer against answers known in closed form, on llvmpipe at tiny sizes:
//  - white furnace: a closed sphere that emits Le and reflects with albedo a on its
//    inside has radiance Le / (1 - a) everywhere; with max depth d (no roulette) it is
//    Le (1 - a^d) / (1 - a), so each added bounce adds exactly Le a^(d-1): energy
//    never grows beyond what a bounce can carry;
//  - a Lambertian plane under a point light: L = albedo I h / (pi d^3);
//  - no NaN or Inf at grazing angles, at a light, or next to a point light;
//  - a seed fixes the image; the Cornell room's mean converges;
//  - the std430/std140 layouts of pathtrace_shared.h agree with C++.
// Every test but the layout check runs on both devices (gl: the compute shader;
// cpu: Embree), as PathtraceTest/Gl.* and PathtraceTest/Cpu.*.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <random>
#include <utility>

#include "pathtrace_shared.h"
#include "render/bvh.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"

namespace voxgi::test {
namespace {

constexpr float kPi = 3.14159265358979f;

scene::Scene sceneOf(std::vector<scene::Vertex> vertices, std::vector<uint32_t> indices,
                     const scene::Material& material, const scene::Camera& camera) {
  scene::Scene s;
  s.path = "test";
  s.vertices = std::move(vertices);
  s.indices = std::move(indices);
  s.materials.push_back(material);
  s.draws.push_back({0, static_cast<uint32_t>(s.indices.size()), 0, -1, -1});
  s.camera = camera;
  s.camera.fromFile = true;
  s.finalize();
  return s;
}

// A UV sphere with flat facets (each triangle its own vertices and normal), so the
// enclosure is exactly what the path tracer sees.
scene::Scene furnace(float albedo, float le) {
  constexpr int kSeg = 24, kRings = 12;
  auto point = [](int i, int j) {
    const float phi = 2.0f * kPi * static_cast<float>(i) / kSeg;
    const float theta = kPi * static_cast<float>(j) / kRings;
    return glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                     std::sin(theta) * std::sin(phi));
  };
  std::vector<scene::Vertex> v;
  std::vector<uint32_t> idx;
  auto tri = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const glm::vec3 n = glm::cross(b - a, c - a);
    if (glm::length(n) < 1e-9f) return;
    for (const glm::vec3& p : {a, b, c}) {
      idx.push_back(static_cast<uint32_t>(v.size()));
      v.push_back({p, glm::normalize(n), glm::vec2(0.0f)});
    }
  };
  for (int j = 0; j < kRings; ++j)
    for (int i = 0; i < kSeg; ++i) {
      tri(point(i, j), point(i + 1, j + 1), point(i, j + 1));
      tri(point(i, j), point(i + 1, j), point(i + 1, j + 1));
    }
  scene::Material m;
  m.baseColor = glm::vec4(glm::vec3(albedo), 1.0f);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.emission = glm::vec3(le);
  m.doubleSided = true;
  scene::Camera cam;
  cam.position = glm::vec3(0.1f, -0.2f, 0.3f);
  cam.forward = glm::normalize(glm::vec3(0.2f, 0.1f, -1.0f));
  cam.yfov = 1.2f;
  return sceneOf(std::move(v), std::move(idx), m, cam);
}

struct Settings {
  int size = 16;
  int spp = 16;
  int maxDepth = 8;
  int rrDepth = 5;
  uint32_t seed = 0;
  bool nee = true;
};

}  // namespace
}  // namespace voxgi::test

namespace voxgi::render {
// Test names and failure messages name the device.
void PrintTo(PathtraceDevice d, std::ostream* os) {
  *os << pathtraceDeviceName(d);
}
}  // namespace voxgi::render

namespace voxgi::test {
namespace {

// The device the current test runs on (set by the fixture from its parameter).
render::PathtraceDevice gDevice = render::PathtraceDevice::kGl;

std::vector<float> renderLinear(const scene::Scene& s, const Settings& t) {
  gl::ProgramCache programs(sourceDir() + "/shaders");
  render::RenderSettings rs;
  rs.width = rs.height = t.size;
  rs.mode = render::Mode::kPathtrace;
  rs.spp = t.spp;
  rs.pathtrace.maxDepth = t.maxDepth;
  rs.pathtrace.rrDepth = t.rrDepth;
  rs.pathtrace.seed = t.seed;
  rs.pathtrace.nextEventEstimation = t.nee;
  rs.pathtrace.device = gDevice;
  render::Renderer r(programs, s, rs);
  r.renderFrame();
  EXPECT_EQ(r.pathtrace()->device(), gDevice);
  EXPECT_EQ(r.pathtrace()->truncatedPaths(), 0u) << "paths cut short by the loop budget";
  return r.readLinear();
}

// Mean over pixels of the RGB average.
double meanRgb(const std::vector<float>& px) {
  double sum = 0.0;
  for (size_t i = 0; i < px.size(); i += 4) sum += (px[i] + px[i + 1] + px[i + 2]) / 3.0;
  return sum / static_cast<double>(px.size() / 4);
}

bool allFinite(const std::vector<float>& px) {
  for (float v : px)
    if (!std::isfinite(v)) return false;
  return true;
}

class PathtraceTest : public GlTest, public ::testing::WithParamInterface<render::PathtraceDevice> {
 protected:
  void SetUp() override {
    GlTest::SetUp();
    gDevice = GetParam();
  }
};

class PathtraceGlTest : public GlTest {};

TEST_P(PathtraceTest, WhiteFurnaceConvergesToClosedForm) {
  const float a = 0.5f, le = 1.0f;
  const scene::Scene s = furnace(a, le);
  Settings t;
  t.size = 32;
  t.spp = 32;
  t.maxDepth = 1024;  // long enough that the truncated series is within 1e-9 of the limit
  const auto px = renderLinear(s, t);
  ASSERT_TRUE(allFinite(px));
  const double expected = le / (1.0 - a);
  const double got = meanRgb(px);
  std::printf("furnace a=%.2f: mean %.5f, expected %.5f (%.3f%% off)\n", a, got, expected,
              100.0 * (got / expected - 1.0));
  // Five seeds: -0.085% to +0.056% off, standard deviation 0.058%; the bound is 4 of it.
  EXPECT_NEAR(got, expected, 0.0025 * expected);
}

TEST_P(PathtraceTest, EachBounceAddsExactlyWhatItCarries) {
  const float a = 0.6f, le = 1.0f;
  const scene::Scene s = furnace(a, le);
  Settings t;
  t.spp = 16;
  t.rrDepth = 1000;  // no roulette: each depth is the exact truncated series
  double previous = 0.0, previousStep = 1e30;
  for (int depth = 1; depth <= 6; ++depth) {
    t.maxDepth = depth;
    const double got = meanRgb(renderLinear(s, t));
    const double expected = le * (1.0 - std::pow(a, depth)) / (1.0 - a);
    std::printf("furnace max depth %d: %.5f, expected %.5f\n", depth, got, expected);
    // Five seeds at depth 6, the noisiest: -0.14% to +0.07%, standard deviation
    // 0.08%; the bound is 4 of it.
    EXPECT_NEAR(got, expected, 0.0035 * expected) << "max depth " << depth;
    const double step = got - previous;
    EXPECT_GT(step, 0.0) << "max depth " << depth;
    EXPECT_LT(step, previousStep) << "bounce " << depth << " carried more than the one before";
    previous = got;
    previousStep = step;
  }
}

// A mirror enclosure (metallic 1, roughness 0: reflectance = base colour, no
// Fresnel) obeys the same series; every path is deterministic after the first ray.
TEST_P(PathtraceTest, MirrorFurnaceMatchesClosedForm) {
  const float rho = 0.5f;
  scene::Scene s = furnace(rho, 1.0f);
  s.materials[0].metallic = 1.0f;
  s.materials[0].roughness = 0.0f;
  Settings t;
  t.maxDepth = 6;
  t.rrDepth = 1000;
  const double got = meanRgb(renderLinear(s, t));
  const double expected = (1.0 - std::pow(rho, 6)) / (1.0 - rho);
  std::printf("mirror furnace: %.6f, expected %.6f\n", got, expected);
  EXPECT_NEAR(got, expected, 1e-4 * expected);
}

// Light sampling with MIS and BSDF sampling alone are two estimators of the same
// integral: they agree only if every pdf (GGX visible normals, the lobe mix, the
// emitters' area pdf) is right. A furnace of glTF metallic-roughness material.
TEST_P(PathtraceTest, LightSamplingAndBsdfSamplingAgreeOnGgx) {
  scene::Scene s = furnace(0.8f, 1.0f);
  // Per material, the bound is 4 standard deviations of the two estimators'
  // relative difference over five seeds (0.19%, 0.085% and 0.03%).
  for (auto [metallic, roughness, bound] :
       {std::tuple{0.0f, 0.3f, 0.0075}, std::tuple{0.5f, 0.5f, 0.0035},
        std::tuple{1.0f, 0.2f, 0.0012}}) {
    s.materials[0].metallic = metallic;
    s.materials[0].roughness = roughness;
    Settings t;
    t.size = 24;
    t.spp = 32;
    t.maxDepth = 4;
    const double withNee = meanRgb(renderLinear(s, t));
    t.nee = false;
    t.seed = 1;
    const double bsdfOnly = meanRgb(renderLinear(s, t));
    std::printf("metallic %.1f roughness %.1f: NEE + MIS %.5f, BSDF sampling %.5f\n", metallic,
                roughness, withNee, bsdfOnly);
    EXPECT_NEAR(withNee, bsdfOnly, bound * bsdfOnly) << metallic << " " << roughness;
    EXPECT_GT(withNee, 1.0);  // emission plus something reflected
  }
}

// A 20 m Lambertian plane seen from above, lit by a point light at height h.
scene::Scene planeUnderPointLight(float albedo, float intensity, float h,
                                  const scene::Camera& cam) {
  const float r = 10.0f;
  std::vector<scene::Vertex> v = {{{-r, 0, r}, {0, 1, 0}, {}},
                                  {{r, 0, r}, {0, 1, 0}, {}},
                                  {{r, 0, -r}, {0, 1, 0}, {}},
                                  {{-r, 0, -r}, {0, 1, 0}, {}}};
  scene::Material m;
  m.baseColor = glm::vec4(glm::vec3(albedo), 1.0f);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  scene::Scene s = sceneOf(std::move(v), {0, 1, 2, 0, 2, 3}, m, cam);
  scene::Light l;
  l.type = scene::LightType::kPoint;
  l.intensity = intensity;
  l.position = glm::vec3(0.0f, h, 0.0f);
  s.lights.push_back(l);
  return s;
}

TEST_P(PathtraceTest, PlaneUnderPointLightMatchesClosedForm) {
  const float albedo = 0.8f, intensity = 2.0f, h = 1.0f;
  scene::Camera cam;
  cam.position = glm::vec3(0.0f, 3.0f, 0.0f);
  cam.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  cam.up = glm::vec3(0.0f, 0.0f, -1.0f);
  cam.yfov = 1.0f;
  const scene::Scene s = planeUnderPointLight(albedo, intensity, h, cam);
  Settings t;
  t.size = 24;
  t.spp = 1024;  // the footprint average: per-pixel jitter noise well under 1%
  const auto px = renderLinear(s, t);
  ASSERT_TRUE(allFinite(px));
  // The closed form averaged over each pixel's footprint (box filter), 16x16 points.
  const float tanHalf = std::tan(0.5f * cam.yfov);
  double worst = 0.0, sumGot = 0.0, sumExpected = 0.0;
  for (int row = 0; row < t.size; ++row) {
    const int y = t.size - 1 - row;  // readLinear is top-down; GL y grows upwards
    for (int x = 0; x < t.size; ++x) {
      double expected = 0.0;
      for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) {
          const float nx = ((static_cast<float>(x) + (i + 0.5f) / 16.0f) / t.size) * 2.0f - 1.0f;
          const float ny = ((static_cast<float>(y) + (j + 0.5f) / 16.0f) / t.size) * 2.0f - 1.0f;
          const glm::vec3 d = glm::normalize(glm::vec3(nx * tanHalf, -1.0f, -ny * tanHalf));
          const glm::vec3 p = cam.position + d * (cam.position.y / -d.y);
          const float dist = glm::length(glm::vec3(0.0f, h, 0.0f) - p);
          expected += albedo * intensity * h / (kPi * dist * dist * dist) / 256.0;
        }
      const size_t k = (static_cast<size_t>(row) * t.size + static_cast<size_t>(x)) * 4;
      sumGot += px[k];
      sumExpected += expected;
      for (int c = 0; c < 3; ++c) {
        const double err = std::abs(px[k + static_cast<size_t>(c)] / expected - 1.0);
        worst = std::max(worst, err);
      }
    }
  }
  std::printf("plane under a point light: worst pixel %.3f%%, mean %.4f%% off the closed form\n",
              100 * worst, 100 * (sumGot / sumExpected - 1.0));
  // Five seeds: worst pixel 0.50% to 0.62%, mean -0.005% to +0.006% off.
  EXPECT_LT(worst, 0.008);
  EXPECT_NEAR(sumGot / sumExpected, 1.0, 0.0003);
}

// The same plane under a small one-sided sphere lamp of radiance le, radius rl,
// centre (0, h, 0), tessellated finely (outward facets): direct light only (max
// depth 2) reflects L = albedo le rl^2 h / d^3 (the closed form of a uniform sphere
// lamp wholly above the horizon, d the distance to its centre). The plane makes the
// scene large next to the lamp, so the shadow rays' offset from the plane is many
// times what separates a sampled point from the lamp's neighbouring facets.
TEST_P(PathtraceTest, PlaneUnderTessellatedSphereLampMatchesClosedForm) {
  const float albedo = 0.75f, le = 100.0f, rl = 0.08f, h = 1.3f;
  scene::Camera cam;
  cam.position = glm::vec3(0.0f, 0.2f, 1.5f);
  cam.forward = glm::vec3(0.0f, -1.0f, 0.0f);
  cam.up = glm::vec3(0.0f, 0.0f, -1.0f);
  cam.yfov = 0.2f;
  scene::Scene s = planeUnderPointLight(albedo, 1.0f, h, cam);
  s.lights.clear();
  constexpr int kSeg = 64, kRings = 32;
  auto point = [&](int i, int j) {
    const float phi = 2.0f * kPi * static_cast<float>(i) / kSeg;
    const float theta = kPi * static_cast<float>(j) / kRings;
    return glm::vec3(0.0f, h, 0.0f) + rl * glm::vec3(std::sin(theta) * std::cos(phi),
                                                     std::cos(theta),
                                                     std::sin(theta) * std::sin(phi));
  };
  const auto first = static_cast<uint32_t>(s.indices.size());
  auto tri = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const glm::vec3 n = glm::cross(b - a, c - a);
    if (glm::length(n) < 1e-12f) return;
    for (const glm::vec3& p : {a, b, c}) {
      s.indices.push_back(static_cast<uint32_t>(s.vertices.size()));
      s.vertices.push_back({p, glm::normalize(n), glm::vec2(0.0f)});
    }
  };
  for (int j = 0; j < kRings; ++j)
    for (int i = 0; i < kSeg; ++i) {
      tri(point(i, j), point(i + 1, j + 1), point(i, j + 1));
      tri(point(i, j), point(i + 1, j), point(i + 1, j + 1));
    }
  scene::Material lamp;
  lamp.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  lamp.emission = glm::vec3(le);
  lamp.doubleSided = false;
  s.materials.push_back(lamp);
  s.draws.push_back({first, static_cast<uint32_t>(s.indices.size()) - first, 1, -1, -1});
  s.finalize();
  Settings t;
  t.size = 16;
  t.spp = 1024;
  t.maxDepth = 2;
  const auto px = renderLinear(s, t);
  ASSERT_TRUE(allFinite(px));
  // The closed form averaged over the image's footprint, 64x64 points.
  const float tanHalf = std::tan(0.5f * cam.yfov);
  double expected = 0.0;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      const float nx = (static_cast<float>(i) + 0.5f) / 32.0f - 1.0f;
      const float ny = (static_cast<float>(j) + 0.5f) / 32.0f - 1.0f;
      const glm::vec3 d = glm::normalize(glm::vec3(nx * tanHalf, -1.0f, -ny * tanHalf));
      const glm::vec3 p = cam.position + d * (cam.position.y / -d.y);
      const float dist = glm::length(glm::vec3(0.0f, h, 0.0f) - p);
      expected += albedo * le * rl * rl * h / (dist * dist * dist) / 4096.0;
    }
  const double got = meanRgb(px);
  std::printf("plane under a tessellated sphere lamp: %.5f, expected %.5f (%.2f%% off)\n", got,
              expected, 100.0 * (got / expected - 1.0));
  EXPECT_NEAR(got, expected, 0.03 * expected);
}

TEST_P(PathtraceTest, NoNanAtGrazingAnglesOrAtLights) {
  // Grazing: the camera 1 mm above the plane, looking along it; a second point light
  // lies in the plane itself.
  scene::Camera cam;
  cam.position = glm::vec3(0.0f, 0.001f, 5.0f);
  cam.forward = glm::normalize(glm::vec3(0.0f, -0.0001f, -1.0f));
  scene::Scene s = planeUnderPointLight(0.8f, 5.0f, 0.5f, cam);
  scene::Light inPlane = s.lights[0];
  inPlane.position = glm::vec3(0.0f, 0.0f, 2.0f);
  s.lights.push_back(inPlane);
  Settings t;
  t.size = 16;
  t.spp = 8;
  EXPECT_TRUE(allFinite(renderLinear(s, t))) << "grazing";

  // At the light: the Cornell room seen from 1 mm below its panel, and from above it.
  scene::Scene room = scene::loadGltf(cornellRoom());
  for (float y : {1.989f, 1.995f}) {
    room.camera.position = glm::vec3(0.0f, y, 0.0f);
    room.camera.forward = glm::normalize(glm::vec3(0.01f, 1.0f, 0.0f));
    room.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
    EXPECT_TRUE(allFinite(renderLinear(room, t))) << "camera at y = " << y;
  }
}

TEST_P(PathtraceTest, SeedFixesTheImage) {
  const scene::Scene s = furnace(0.7f, 1.0f);
  Settings t;
  t.size = 16;
  t.spp = 4;
  t.seed = 5;
  const auto a = renderLinear(s, t);
  const auto b = renderLinear(s, t);
  EXPECT_EQ(a, b);
  t.seed = 6;
  EXPECT_NE(a, renderLinear(s, t));
}

// The Cornell room's mean: independent low-spp estimates agree with a higher-spp
// one within their spread (the 1024-spp figure in the README uses the same check).
TEST_P(PathtraceTest, CornellMeanConverges) {
  const scene::Scene s = scene::loadGltf(cornellRoom());
  Settings t;
  t.size = 32;
  t.spp = 32;
  std::vector<double> means;
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    t.seed = seed;
    means.push_back(meanRgb(renderLinear(s, t)));
  }
  const double m = std::accumulate(means.begin(), means.end(), 0.0) / 4.0;
  double var = 0.0;
  for (double x : means) var += (x - m) * (x - m) / 3.0;
  const double se = std::sqrt(var / 4.0);
  t.seed = 100;
  t.spp = 256;
  const double hi = meanRgb(renderLinear(s, t));
  // The 256-spp estimate has about a third of the spread of one 32-spp estimate.
  const double tolerance = 4.0 * std::sqrt(se * se + var / 8.0) + 1e-4;
  std::printf("cornell_room 32x32: mean of 4 x 32 spp %.5f +- %.5f, 256 spp %.5f\n", m, se, hi);
  EXPECT_NEAR(hi, m, tolerance);
  EXPECT_GT(m, 0.05);
  EXPECT_LT(se / m, 0.05);
}

// The GPU traversal against the CPU one: a soup of emissive triangles seen directly
// (max depth 1) covers each pixel exactly as much as CPU rays through the same
// footprint find; a dropped leaf or a wrong box test leaves holes.
TEST_P(PathtraceTest, GpuCoverageMatchesCpuTraversal) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f), off(-0.12f, 0.12f);
  std::vector<scene::Vertex> v;
  std::vector<uint32_t> idx;
  std::vector<render::BvhTriangle> tris;
  for (int i = 0; i < 1500; ++i) {
    const glm::vec3 c(pos(rng), pos(rng), pos(rng));
    render::BvhTriangle t{c + glm::vec3(off(rng), off(rng), off(rng)),
                          c + glm::vec3(off(rng), off(rng), off(rng)),
                          c + glm::vec3(off(rng), off(rng), off(rng))};
    const glm::vec3 n = glm::cross(t.v1 - t.v0, t.v2 - t.v0);
    if (glm::length(n) < 1e-4f) continue;
    tris.push_back(t);
    for (const glm::vec3& p : {t.v0, t.v1, t.v2}) {
      idx.push_back(static_cast<uint32_t>(v.size()));
      v.push_back({p, glm::normalize(n), glm::vec2(0.0f)});
    }
  }
  scene::Material m;
  m.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  m.emission = glm::vec3(1.0f);
  m.doubleSided = true;
  scene::Camera cam;
  cam.position = glm::vec3(0.0f, 0.0f, 4.0f);
  cam.yfov = 0.8f;
  const scene::Scene s = sceneOf(std::move(v), std::move(idx), m, cam);
  Settings t;
  t.size = 24;
  t.spp = 256;
  t.maxDepth = 1;
  const auto px = renderLinear(s, t);
  const render::Bvh bvh(tris);
  const float tanHalf = std::tan(0.5f * cam.yfov);
  double sum = 0.0, worst = 0.0, covered = 0.0;
  for (int row = 0; row < t.size; ++row) {
    const int y = t.size - 1 - row;
    for (int x = 0; x < t.size; ++x) {
      int hits = 0;
      for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) {
          const float nx = ((static_cast<float>(x) + (i + 0.5f) / 16.0f) / t.size) * 2.0f - 1.0f;
          const float ny = ((static_cast<float>(y) + (j + 0.5f) / 16.0f) / t.size) * 2.0f - 1.0f;
          const glm::vec3 d = glm::normalize(glm::vec3(nx * tanHalf, ny * tanHalf, -1.0f));
          if (bvh.occluded({cam.position, d})) ++hits;
        }
      const double expected = hits / 256.0;
      const double got = px[(static_cast<size_t>(row) * t.size + static_cast<size_t>(x)) * 4];
      sum += got - expected;
      covered += expected;
      worst = std::max(worst, std::abs(got - expected));
    }
  }
  const double bias = sum / (t.size * t.size);
  std::printf("coverage %.3f: mean GPU - CPU %.5f, worst pixel %.4f\n", covered / (t.size * t.size),
              bias, worst);
  EXPECT_LT(std::abs(bias), 0.003);  // one missing triangle of this soup costs more
  EXPECT_LT(worst, 0.2);             // jitter noise at a partly covered pixel: sd <= 0.5 / 16
}

// Base-colour textures: a quad facing the camera, its texture red on the left half
// and green on the right, lit along the view by a directional light of irradiance
// pi, so that radiance equals the albedo. Bilinear texels repeat as in the raster
// sampler; with the effect plan's `-textures` the same quad is its white base colour.
TEST_P(PathtraceTest, BaseColourTexturesMapOntoTheSurface) {
  std::vector<scene::Vertex> v;
  for (glm::vec2 p : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
    v.push_back({glm::vec3(p, 0.0f), glm::vec3(0, 0, 1), glm::vec2((p.x + 1) / 2, (1 - p.y) / 2)});
  scene::Material m;
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.baseColorTexture = 0;
  scene::Camera cam;
  cam.position = glm::vec3(0, 0, 2);
  cam.yfov = 2.0f * std::atan(0.4f);  // the image spans x, y in [-0.8, 0.8]: u in [0.1, 0.9]
  scene::Scene s = sceneOf(v, {0, 1, 2, 0, 2, 3}, m, cam);
  scene::Texture t;
  t.width = t.height = 4;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      for (uint8_t c :
           {uint8_t(x < 2 ? 255 : 0), uint8_t(x < 2 ? 0 : 255), uint8_t(0), uint8_t(255)})
        t.rgba8.push_back(c);
  s.textures.push_back(t);
  scene::Light sun;
  sun.type = scene::LightType::kDirectional;
  sun.direction = glm::vec3(0, 0, -1);
  sun.intensity = kPi;
  s.lights.push_back(sun);

  auto render = [&](const std::string& effects) {
    gl::ProgramCache programs(sourceDir() + "/shaders");
    render::RenderSettings rs;
    rs.width = rs.height = 40;
    rs.mode = render::Mode::kPathtrace;
    rs.spp = 4;
    rs.effects = effects;
    rs.pathtrace.device = gDevice;
    render::Renderer r(programs, s, rs);
    r.renderFrame();
    return r.readLinear();
  };
  // Columns where u is a pure texel colour: u in [0.125, 0.375] (red) and [0.625,
  // 0.875] (green), i.e. x in [-0.75, -0.25] and [0.25, 0.75] of [-0.8, 0.8].
  auto columnMeans = [](const std::vector<float>& px, float x0, float x1) {
    glm::dvec3 sum(0.0);
    int n = 0;
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) {
        const float cx = -0.8f + 1.6f * (static_cast<float>(x) + 0.5f) / 40.0f;
        if (cx < x0 + 0.05f || cx > x1 - 0.05f) continue;
        const size_t i = (static_cast<size_t>(y) * 40 + static_cast<size_t>(x)) * 4;
        sum += glm::dvec3(px[i], px[i + 1], px[i + 2]);
        ++n;
      }
    return sum / static_cast<double>(n);
  };
  const auto textured = render("");
  ASSERT_TRUE(allFinite(textured));
  const glm::dvec3 left = columnMeans(textured, -0.75f, -0.25f);
  const glm::dvec3 right = columnMeans(textured, 0.25f, 0.75f);
  std::printf("textured quad: left (%.3f, %.3f, %.3f), right (%.3f, %.3f, %.3f)\n", left.r, left.g,
              left.b, right.r, right.g, right.b);
  EXPECT_NEAR(left.r, 1.0, 0.02);
  EXPECT_LT(left.g, 0.01);
  EXPECT_NEAR(right.g, 1.0, 0.02);
  EXPECT_LT(right.r, 0.01);
  EXPECT_LT(left.b + right.b, 0.01);
  const auto plain = render("-textures");
  const glm::dvec3 whiteLeft = columnMeans(plain, -0.75f, -0.25f);
  EXPECT_NEAR(whiteLeft.r, 1.0, 0.02);
  EXPECT_NEAR(whiteLeft.g, 1.0, 0.02);
}

// Lambert of `albedo` (metallic 0, roughness 1), opaque.
scene::Material lambert(glm::vec3 albedo) {
  scene::Material m;
  m.baseColor = glm::vec4(albedo, 1.0f);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  return m;
}

// A white Lambertian plane at z = 0 and a 4 x 4 quad of material `front` at z = 1
// (uv across it), seen from (0, 0, 3), where the quad fills the view (x, y in
// [-0.5, 0.5] at it), lit along the view by a directional light of irradiance pi: the
// lit plane's radiance is 1.
scene::Scene quadBeforeLitPlane(const scene::Material& front,
                                std::vector<scene::Texture> textures = {}) {
  std::vector<scene::Vertex> v;
  for (float z : {0.0f, 1.0f})
    for (glm::vec2 p : {glm::vec2(-2, -2), glm::vec2(2, -2), glm::vec2(2, 2), glm::vec2(-2, 2)})
      v.push_back({glm::vec3(p, z), glm::vec3(0, 0, 1), glm::vec2((p.x + 2) / 4, (2 - p.y) / 4)});
  scene::Camera cam;
  cam.position = glm::vec3(0, 0, 3);
  cam.yfov = 2.0f * std::atan(0.25f);
  scene::Scene s = sceneOf(v, {0, 1, 2, 0, 2, 3}, lambert(glm::vec3(1.0f)), cam);
  s.materials.push_back(front);
  for (uint32_t i : {4u, 5u, 6u, 4u, 6u, 7u}) s.indices.push_back(i);
  s.draws.push_back({6, 6, 1, -1, -1});
  s.textures = std::move(textures);
  scene::Light sun;
  sun.type = scene::LightType::kDirectional;
  sun.direction = glm::vec3(0, 0, -1);
  sun.intensity = kPi;
  s.lights.push_back(sun);
  s.finalize();
  return s;
}

// An alpha-masked quad (glTF MASK, cutoff 0.5), black, whose texture is transparent on
// its left half, in front of the lit plane (quadBeforeLitPlane). Through the cut-out,
// the camera sees the plane, and the plane is lit through it: camera rays and shadow
// rays both pass the mask. The opaque half is black.
TEST_P(PathtraceTest, AlphaMaskedTexelsLetRaysThrough) {
  scene::Material mask = lambert(glm::vec3(0.0f));
  mask.baseColorTexture = 0;
  mask.alphaMode = scene::AlphaMode::kMask;
  mask.alphaCutoff = 0.5f;
  scene::Texture t;
  t.width = t.height = 4;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      for (uint8_t c : {uint8_t(255), uint8_t(255), uint8_t(255), uint8_t(x < 2 ? 0 : 255)})
        t.rgba8.push_back(c);
  const scene::Scene s = quadBeforeLitPlane(mask, {t});
  Settings r;
  r.size = 16;
  r.spp = 4;
  const auto px = renderLinear(s, r);
  ASSERT_TRUE(allFinite(px));
  // Columns well inside each half (x in [-0.5, 0.5] at the quad; u = (x + 2) / 4).
  double left = 0.0, right = 0.0;
  int n = 0;
  for (int y = 0; y < r.size; ++y)
    for (int x = 0; x < 4; ++x) {
      left += px[(static_cast<size_t>(y) * r.size + static_cast<size_t>(x)) * 4];
      right += px[(static_cast<size_t>(y) * r.size + static_cast<size_t>(r.size - 1 - x)) * 4];
      ++n;
    }
  left /= n;
  right /= n;
  std::printf("masked quad: through the cut-out %.4f (lit plane: 1), opaque half %.4f\n", left,
              right);
  EXPECT_NEAR(left, 1.0, 0.01);
  EXPECT_LT(right, 0.01);
}

// A blended quad (glTF BLEND) of alpha 0.25, black, in front of the lit plane
// (quadBeforeLitPlane): a camera ray passes it with probability 0.75 and sees the
// plane, whose shadow ray passes it with probability 0.75, so the image is 0.75 x
// 0.75 = 0.5625 of the lit plane. Drawn opaque, it would be black; ignored, 1. 16 x
// 16 pixels x 16 samples: the mean of 4096 draws of 0 or 1 at 0.5625 has a standard
// deviation of 0.008.
TEST_P(PathtraceTest, BlendedSurfacesCoverTheirAlpha) {
  scene::Material glass = lambert(glm::vec3(0.0f));
  glass.baseColor.a = 0.25f;
  glass.alphaMode = scene::AlphaMode::kBlend;
  const scene::Scene s = quadBeforeLitPlane(glass);
  Settings r;
  r.size = 16;
  r.spp = 16;
  const auto px = renderLinear(s, r);
  ASSERT_TRUE(allFinite(px));
  double mean = 0.0;
  for (size_t i = 0; i < px.size(); i += 4) mean += px[i];
  mean /= static_cast<double>(px.size() / 4);
  std::printf("blended quad of alpha 0.25: %.4f (expected 0.5625)\n", mean);
  EXPECT_NEAR(mean, 0.5625, 0.03);
}

// Both devices render the same image on every scene in scenes/: with the same seed
// their random streams agree and every decision is made by the same shared code,
// so paths match sample for sample, and only a rounding difference in a hit point
// lets a path part ways. Measured: RMSE gl-cpu 0 to 1e-3 where two seeds on one
// device differ by 2e-3 to 1.2. Bound: a tenth of the seed-to-seed RMSE, and the
// means within 0.1% (or a tenth of the seed-to-seed change). A material, texture or
// light that one device reads differently breaks this on the first bright pixel.
TEST_F(PathtraceGlTest, DevicesAgreeOnEverySampleScene) {
  std::vector<std::string> files;
  for (const auto& dir : std::filesystem::directory_iterator(samplesDir())) {
    if (!dir.is_directory()) continue;
    for (const auto& f : std::filesystem::directory_iterator(dir.path()))
      if (f.path().extension() == ".gltf" || f.path().extension() == ".glb")
        files.push_back(f.path().string());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 9u);
  for (const std::string& file : files) {
    const scene::Scene s = scene::loadGltf(file);
    Settings t;
    t.size = 24;
    t.spp = 32;
    gDevice = render::PathtraceDevice::kGl;
    const auto gl = renderLinear(s, t);
    t.seed = 1;
    const auto glOther = renderLinear(s, t);
    t.seed = 0;
    gDevice = render::PathtraceDevice::kCpu;
    const auto cpu = renderLinear(s, t);
    auto rmse = [](const std::vector<float>& a, const std::vector<float>& b) {
      double sum = 0.0;
      for (size_t i = 0; i < a.size(); ++i)
        if (i % 4 != 3) sum += (a[i] - b[i]) * (a[i] - b[i]);
      return std::sqrt(sum / static_cast<double>(a.size() / 4 * 3));
    };
    const double devices = rmse(gl, cpu), seeds = rmse(gl, glOther);
    const double mGl = meanRgb(gl), mCpu = meanRgb(cpu), mOther = meanRgb(glOther);
    const std::string name = std::filesystem::path(file).filename().string();
    std::printf("%-40s mean gl %.5f cpu %.5f (gl seed 1: %.5f); RMSE gl-cpu %.5f, seed 0-1 %.5f\n",
                name.c_str(), mGl, mCpu, mOther, devices, seeds);
    ASSERT_TRUE(allFinite(cpu)) << name;
    EXPECT_LE(devices, 0.1 * seeds) << name;
    EXPECT_LE(std::abs(mCpu - mGl), 0.1 * std::abs(mOther - mGl) + 1e-3 * mGl) << name;
  }
}

// A mesh that moves is traced where the pose puts it: a renderer posed after its
// first frame gives the image of one made at that pose (moving_box.gltf: the box
// slides 1 m along x in its first second), on both devices.
TEST_F(PathtraceGlTest, APosedMeshIsTracedWhereItIs) {
  for (render::PathtraceDevice device :
       {render::PathtraceDevice::kGl, render::PathtraceDevice::kCpu}) {
    SCOPED_TRACE(render::pathtraceDeviceName(device));
    render::RenderSettings rs;
    rs.mode = render::Mode::kPathtrace;
    rs.width = rs.height = 48;
    rs.spp = 4;
    rs.pathtrace.device = device;
    gl::ProgramCache programs(sourceDir() + "/shaders");
    scene::Scene moved = scene::loadGltf(testDataDir() + "/animated/moving_box.gltf");
    ASSERT_TRUE(moved.meshesAnimated());
    render::Renderer r(programs, moved, rs);
    r.renderFrame();
    const std::vector<float> before = r.readLinear();
    moved.pose(1.0);
    r.posed();
    r.renderFrame();
    const std::vector<float> after = r.readLinear();
    scene::Scene fresh = scene::loadGltf(testDataDir() + "/animated/moving_box.gltf");
    fresh.pose(1.0);
    render::Renderer f(programs, fresh, rs);
    f.renderFrame();
    const std::vector<float> expected = f.readLinear();
    double moving = 0.0, off = 0.0;
    for (size_t i = 0; i < expected.size(); ++i) {
      moving += std::abs(before[i] - expected[i]);
      off += std::abs(after[i] - expected[i]);
    }
    std::printf("%s: the pose changes %.3f of the image; posed against fresh %.3g\n",
                render::pathtraceDeviceName(device), moving, off);
    EXPECT_GT(moving, 1.0);  // the box did move in view
    EXPECT_EQ(off, 0.0);
  }
}

TEST_F(PathtraceGlTest, SharedLayoutsMatchCpp) {
  gl::ProgramCache cache(sourceDir() + "/shaders");
  const GLuint p = cache.get({{"render/pathtrace.comp"}, {}}).id();
  auto query = [&](GLenum iface, const char* name, GLenum prop) {
    const GLuint index = glGetProgramResourceIndex(p, iface, name);
    EXPECT_NE(index, GL_INVALID_INDEX) << name;
    GLint v = -1;
    if (index != GL_INVALID_INDEX)
      glGetProgramResourceiv(p, iface, index, 1, &prop, 1, nullptr, &v);
    return v;
  };
  const GLenum bv = GL_BUFFER_VARIABLE;
  // Nodes and triangles are buffer textures of 16-byte texels (pathtrace.comp's
  // loadNode / loadTriangle): their layout is the C++ one, asserted in the header.
  // The scene's indices, which each triangle's record points into, are a uint array.
  EXPECT_EQ(query(bv, "sceneIndices[0]", GL_ARRAY_STRIDE), 4);
  EXPECT_EQ(query(bv, "emissive[0].v0", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(gpu::GpuPtEmissive)));
  EXPECT_EQ(query(bv, "emissive[0].radiance", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuPtEmissive, radiance)));
  GLint group[3] = {0, 0, 0};
  glGetProgramiv(p, GL_COMPUTE_WORK_GROUP_SIZE, group);
  EXPECT_EQ(group[0], static_cast<GLint>(gpu::kPtGroupX));
  EXPECT_EQ(group[1], static_cast<GLint>(gpu::kPtGroupY));
  EXPECT_EQ(query(GL_UNIFORM, "params.image", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuPtParams, image)));
  EXPECT_EQ(query(GL_UNIFORM, "params.depth", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuPtParams, depth)));
  EXPECT_EQ(query(GL_UNIFORM, "params.reserved", GL_OFFSET),
            static_cast<GLint>(offsetof(gpu::GpuPtParams, reserved)));
}

INSTANTIATE_TEST_SUITE_P(Devices, PathtraceTest,
                         ::testing::Values(render::PathtraceDevice::kGl,
                                           render::PathtraceDevice::kCpu),
                         [](const ::testing::TestParamInfo<render::PathtraceDevice>& p) {
                           return p.param == render::PathtraceDevice::kGl ? "Gl" : "Cpu";
                         });

}  // namespace
}  // namespace voxgi::test
