// Emitters as area lights: emitterIrradianceFactor (irradiance per unit radiance)
// against closed forms, and buildEmitters' clusters for a tessellated sphere lamp.
#include "scene/emitters.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "support/scene_builder.h"

namespace voxgi::scene {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Form factor from a differential area to a parallel rectangle x * y (in units of
// the height), the area's normal passing through one corner of the rectangle.
double cornerFormFactor(double x, double y) {
  const double sx = std::sqrt(1.0 + x * x), sy = std::sqrt(1.0 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2.0 * kPi);
}

Emitter triangle(const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2,
                 bool twoSided = false) {
  Emitter e;
  e.kind = Emitter::Kind::kTriangle;
  e.v0 = v0;
  e.v1 = v1;
  e.v2 = v2;
  const glm::vec3 c = glm::cross(v1 - v0, v2 - v0);
  e.normal = glm::normalize(c);
  e.area = 0.5f * glm::length(c);
  e.radiance = glm::vec3(1.0f);
  e.twoSided = twoSided;
  return e;
}

// The rectangle [x0,x1] x [z0,z1] at height y, facing down (-y), as two triangles.
std::vector<Emitter> ceilingRect(float x0, float x1, float z0, float z1, float y,
                                 bool twoSided = false) {
  const glm::vec3 a(x0, y, z0), b(x1, y, z0), c(x1, y, z1), d(x0, y, z1);
  std::vector<Emitter> out = {triangle(a, b, c, twoSided), triangle(a, c, d, twoSided)};
  for (const Emitter& e : out) EXPECT_NEAR(e.normal.y, -1.0f, 1e-6f);  // winding faces down
  return out;
}

double factor(const std::vector<Emitter>& emitters, const glm::vec3& p, const glm::vec3& n) {
  double sum = 0.0;
  for (const Emitter& e : emitters) sum += emitterIrradianceFactor(e, p, n);
  return sum;
}

// --- (a) square emitter above a point, against the corner form factor ---------------

TEST(EmitterIrradiance, SquareAboveCentreMatchesFormFactor) {
  const struct {
    float a, h;  // half side, height
  } cases[] = {{0.5f, 1.0f}, {1.0f, 1.0f},  {0.3f, 2.0f},
               {2.0f, 0.5f}, {0.05f, 3.0f}, {10.0f, 0.1f}};
  for (const auto& c : cases) {
    SCOPED_TRACE(testing::Message() << "a=" << c.a << " h=" << c.h);
    const auto square = ceilingRect(-c.a, c.a, -c.a, c.a, c.h);
    const double expected = kPi * 4.0 * cornerFormFactor(c.a / c.h, c.a / c.h);
    const double got = factor(square, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    EXPECT_NEAR(got, expected, 1e-4 * expected);
  }
}

TEST(EmitterIrradiance, SquareAboveCentreAtAnyPosition) {
  // The same geometry moved away from the origin: only relative positions matter.
  const glm::vec3 offset(3.0f, -2.0f, 5.0f);
  const float a = 0.7f, h = 1.3f;
  const auto square =
      ceilingRect(offset.x - a, offset.x + a, offset.z - a, offset.z + a, offset.y + h);
  const double expected = kPi * 4.0 * cornerFormFactor(a / h, a / h);
  EXPECT_NEAR(factor(square, offset, glm::vec3(0.0f, 1.0f, 0.0f)), expected, 1e-4 * expected);
}

TEST(EmitterIrradiance, RectangleAboveCornerMatchesFormFactor) {
  const float w = 1.5f, l = 0.6f, h = 0.8f;
  const auto rect = ceilingRect(0.0f, w, 0.0f, l, h);
  const double expected = kPi * cornerFormFactor(w / h, l / h);
  EXPECT_NEAR(factor(rect, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f)), expected,
              1e-4 * expected);
}

// --- (b) horizon clipping ------------------------------------------------------------

TEST(EmitterIrradiance, HugeEmitterClippedToHorizon) {
  const auto sky = ceilingRect(-5e3f, 5e3f, -5e3f, 5e3f, 1.0f);
  const glm::vec3 p(0.0f);
  EXPECT_NEAR(factor(sky, p, glm::vec3(0.0f, 1.0f, 0.0f)), kPi, 1e-3);
  EXPECT_NEAR(factor(sky, p, glm::vec3(1.0f, 0.0f, 0.0f)), kPi / 2.0, 1e-3);
  EXPECT_NEAR(factor(sky, p, glm::vec3(0.0f, 0.0f, -1.0f)), kPi / 2.0, 1e-3);
  // Tilted 45 degrees: the sky covers the upper part of the hemisphere,
  // E/L = pi (1 + cos 45) / 2.
  EXPECT_NEAR(factor(sky, p, glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f))),
              kPi * (1.0 + std::sqrt(0.5)) / 2.0, 1e-3);
  // Facing away: nothing above the horizon.
  EXPECT_NEAR(factor(sky, p, glm::vec3(0.0f, -1.0f, 0.0f)), 0.0, 1e-6);
}

// --- (c) one-sidedness ---------------------------------------------------------------

TEST(EmitterIrradiance, OneSidedEmitterDarkBehind) {
  const float a = 0.5f, h = 1.0f;
  const auto front = ceilingRect(-a, a, -a, a, h);
  const auto both = ceilingRect(-a, a, -a, a, h, /*twoSided=*/true);
  const double lit = factor(front, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  ASSERT_GT(lit, 0.0);
  // Behind (above) the emitter, facing it.
  const glm::vec3 behind(0.0f, 2.0f * h, 0.0f);
  const glm::vec3 down(0.0f, -1.0f, 0.0f);
  EXPECT_EQ(factor(front, behind, down), 0.0);
  // Two-sided: the mirror image of the front-side receiver gets the same.
  EXPECT_NEAR(factor(both, behind, down), lit, 1e-5 * lit);
  EXPECT_NEAR(factor(both, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f)), lit, 1e-6 * lit);
}

TEST(EmitterIrradiance, OneSidedClusterDarkBehind) {
  Emitter e;
  e.kind = Emitter::Kind::kCluster;
  e.v0 = glm::vec3(0.0f, 1.0f, 0.0f);
  e.normal = glm::vec3(0.0f, -1.0f, 0.0f);
  e.area = 0.01f;
  e.radiance = glm::vec3(1.0f);
  const float front = emitterIrradianceFactor(e, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  // On axis: A / (d^2 + A/pi), the exact value for a disk of area A.
  EXPECT_NEAR(front, 0.01 / (1.0 + 0.01 / kPi), 1e-6);
  EXPECT_EQ(emitterIrradianceFactor(e, glm::vec3(0.0f, 2.0f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f)),
            0.0f);
  e.twoSided = true;
  EXPECT_NEAR(emitterIrradianceFactor(e, glm::vec3(0.0f, 2.0f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f)),
              front, 1e-7);
}

// --- degenerate receivers ----------------------------------------------------------------

TEST(EmitterIrradiance, NoNanOnVertexEdgeOrPlane) {
  // Receivers exactly on a vertex or an edge, inside the triangle, or elsewhere in
  // its plane, for an axis-aligned and a tilted triangle, both windings, one- and
  // two-sided. On the emitter itself the value depends on the side one comes from,
  // but it must be a number in [0, pi]; elsewhere in the plane the emitter is seen
  // edge-on and gives nothing.
  const std::vector<std::array<glm::vec3, 3>> triangles = {
      {glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(1.0f, 1.0f, 0.0f), glm::vec3(0.0f, 1.0f, 1.0f)},
      {glm::vec3(0.1f, 0.2f, 0.3f), glm::vec3(1.3f, 0.7f, -0.2f), glm::vec3(-0.4f, 1.1f, 0.9f)}};
  const std::vector<glm::vec3> normals = {glm::vec3(0.0f, 1.0f, 0.0f),
                                          glm::vec3(0.0f, -1.0f, 0.0f),
                                          glm::vec3(1.0f, 0.0f, 0.0f),
                                          glm::vec3(0.0f, 0.0f, -1.0f),
                                          glm::normalize(glm::vec3(0.3f, 0.5f, 0.2f)),
                                          glm::normalize(glm::vec3(-0.4f, -0.6f, 0.7f)),
                                          glm::normalize(glm::vec3(1.0f, 1.0f, 1.0f))};
  const char* pointNames[] = {"v0",
                              "v1",
                              "v2",
                              "edge v0v1",
                              "edge v1v2",
                              "centroid",
                              "in plane, outside",
                              "in plane, outside (2)"};
  int evaluated = 0;
  std::vector<std::string> bad;
  for (size_t t = 0; t < triangles.size(); ++t) {
    const auto& [v0, v1, v2] = triangles[t];
    const std::vector<glm::vec3> points = {v0,
                                           v1,
                                           v2,
                                           0.5f * (v0 + v1),
                                           0.5f * (v1 + v2),
                                           (v0 + v1 + v2) / 3.0f,
                                           v0 + 2.0f * (v1 - v0),
                                           v0 - (v2 - v0) + 0.5f * (v1 - v0)};
    for (bool twoSided : {false, true}) {
      for (bool flipped : {false, true}) {
        const Emitter e = flipped ? triangle(v0, v2, v1, twoSided) : triangle(v0, v1, v2, twoSided);
        for (size_t i = 0; i < points.size(); ++i) {
          for (size_t j = 0; j < normals.size(); ++j) {
            const float f = emitterIrradianceFactor(e, points[i], normals[j]);
            ++evaluated;
            const bool outside = i >= 6;
            if (!std::isfinite(f) || f < 0.0f || f > static_cast<float>(kPi) * 1.0001f ||
                (outside && std::abs(f) > 1e-4f)) {
              std::ostringstream s;
              s << "triangle " << t << (twoSided ? " two-sided" : " one-sided")
                << (flipped ? " flipped" : "") << ", receiver on " << pointNames[i] << ", normal "
                << j << ": " << f;
              bad.push_back(s.str());
            }
          }
        }
      }
    }
  }
  std::string list;
  for (size_t i = 0; i < bad.size() && i < 12; ++i) list += "\n  " + bad[i];
  if (bad.size() > 12) list += "\n  ... and " + std::to_string(bad.size() - 12) + " more";
  EXPECT_TRUE(bad.empty()) << bad.size() << " of " << evaluated
                           << " evaluations are NaN or out of range:" << list;
  // A cluster evaluated at its own centre.
  Emitter c;
  c.kind = Emitter::Kind::kCluster;
  c.v0 = glm::vec3(0.5f);
  c.normal = glm::vec3(0.0f, 1.0f, 0.0f);
  c.area = 0.1f;
  for (const glm::vec3& n : normals) {
    const float f = emitterIrradianceFactor(c, c.v0, n);
    EXPECT_TRUE(std::isfinite(f)) << f;
    EXPECT_GE(f, 0.0f);
  }
}

TEST(EmitterIrradiance, FiniteJustOffTheEmitter) {
  // Approaching the emitter's surface from the front: finite and bounded by pi
  // (the whole hemisphere covered).
  const auto square = ceilingRect(-1.0f, 1.0f, -1.0f, 1.0f, 1.0f);
  for (float gap : {1e-1f, 1e-3f, 1e-5f, 1e-7f}) {
    for (const glm::vec3& p :
         {glm::vec3(0.0f), glm::vec3(-1.0f, 0.0f, -1.0f), glm::vec3(0.3f, 0.0f, 1.0f)}) {
      const float f =
          static_cast<float>(factor(square, glm::vec3(p.x, 1.0f - gap, p.z), glm::vec3(0, 1, 0)));
      EXPECT_TRUE(std::isfinite(f)) << "gap " << gap;
      EXPECT_GE(f, 0.0f);
      EXPECT_LE(f, static_cast<float>(kPi) * 1.0001f) << "gap " << gap;
    }
  }
}

// --- (d) clusters: a UV-sphere lamp ---------------------------------------------------------

constexpr float kSphereRadius = 0.08f;
const glm::vec3 kSphereCenter(0.2f, 1.3f, -0.4f);

// UV sphere of 128 longitude segments x 64 latitude rings (8385 vertices, 16128
// triangles), counter-clockwise seen from outside; one emissive one-sided material.
Scene sphereLampScene(int segments = 128, int rings = 64) {
  Scene s;
  s.path = "uv_sphere_lamp";
  for (int i = 0; i <= rings; ++i) {
    const double theta = kPi * i / rings;  // from +y
    for (int j = 0; j <= segments; ++j) {
      const double phi = 2.0 * kPi * j / segments;
      const glm::vec3 n(static_cast<float>(std::sin(theta) * std::cos(phi)),
                        static_cast<float>(std::cos(theta)),
                        static_cast<float>(std::sin(theta) * std::sin(phi)));
      s.vertices.push_back(Vertex{kSphereCenter + kSphereRadius * n, n, glm::vec2(0.0f)});
    }
  }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(i * (segments + 1) + j); };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      // d(position)/d(phi) x d(position)/d(theta) points outwards.
      if (i != 0) s.indices.insert(s.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
      if (i != rings - 1)
        s.indices.insert(s.indices.end(), {at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  Material m;
  m.name = "lamp";
  m.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  m.emission = glm::vec3(100.0f);
  m.doubleSided = false;
  s.materials.push_back(m);
  Draw d;
  d.firstIndex = 0;
  d.indexCount = static_cast<uint32_t>(s.indices.size());
  d.material = 0;
  d.node = 0;
  d.mesh = 0;
  s.draws.push_back(d);
  s.finalize();
  return s;
}

class SphereLamp : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(sphereLampScene());
    emitters_ = new std::vector<Emitter>(buildEmitters(*scene_));
  }
  static void TearDownTestSuite() {
    delete emitters_;
    delete scene_;
  }
  static double sumAt(const glm::vec3& p, const glm::vec3& n) { return factor(*emitters_, p, n); }
  static Scene* scene_;
  static std::vector<Emitter>* emitters_;
};
Scene* SphereLamp::scene_ = nullptr;
std::vector<Emitter>* SphereLamp::emitters_ = nullptr;

TEST_F(SphereLamp, FixtureIsAnOutwardSphere) {
  EXPECT_EQ(scene_->vertices.size(), 8385u);
  ASSERT_EQ(scene_->triangleCount(), 16128u);
  double area = 0.0;
  for (size_t t = 0; t < scene_->triangleCount(); ++t) {
    const glm::vec3 a = scene_->vertices[scene_->indices[3 * t]].position;
    const glm::vec3 b = scene_->vertices[scene_->indices[3 * t + 1]].position;
    const glm::vec3 c = scene_->vertices[scene_->indices[3 * t + 2]].position;
    const glm::vec3 cr = glm::cross(b - a, c - a);
    ASSERT_GT(glm::dot(cr, (a + b + c) / 3.0f - kSphereCenter), 0.0f)
        << "triangle " << t << " faces inwards";
    area += 0.5 * glm::length(cr);
  }
  const double sphereArea = 4.0 * kPi * kSphereRadius * kSphereRadius;
  EXPECT_NEAR(area, sphereArea, 2e-3 * sphereArea);  // facets are a hair inside the sphere
}

TEST_F(SphereLamp, GroupedIntoClusters) {
  ASSERT_FALSE(emitters_->empty());
  EXPECT_LT(emitters_->size(), scene_->triangleCount());
  EXPECT_GT(emitters_->size(), 8u);  // more than one group per octant
  for (const Emitter& e : *emitters_) {
    EXPECT_EQ(e.kind, Emitter::Kind::kCluster);
    EXPECT_FALSE(e.twoSided);
    EXPECT_EQ(e.radiance, glm::vec3(100.0f));
    EXPECT_GT(e.area, 0.0f);
    EXPECT_NEAR(glm::length(e.normal), 1.0f, 1e-5f);
    // Centres near the surface and normals pointing outwards.
    EXPECT_LE(glm::length(e.v0 - kSphereCenter), kSphereRadius * 1.0001f);
    EXPECT_GT(glm::dot(e.normal, glm::normalize(e.v0 - kSphereCenter)), 0.8f);
  }
}

TEST_F(SphereLamp, ClusterAreasAddUpToTheSphere) {
  // A cluster's area is its projected area |sum n_i A_i| <= sum A_i: the total can
  // only fall short of the sphere's, by the spread of normals inside each cluster.
  double total = 0.0;
  for (const Emitter& e : *emitters_) total += e.area;
  const double sphereArea = 4.0 * kPi * kSphereRadius * kSphereRadius;
  EXPECT_LE(total, sphereArea * 1.0001);
  EXPECT_GE(total, sphereArea * 0.95);
}

TEST_F(SphereLamp, ProjectedAreaIsADiskFromEveryDirection) {
  // Seen from afar along w, a sphere shows pi r^2: sum_k A_k max(0, n_k . w).
  const double disk = kPi * kSphereRadius * kSphereRadius;
  std::vector<glm::vec3> directions;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if (x || y || z) directions.push_back(glm::normalize(glm::vec3(x, y, z)));
  directions.push_back(glm::normalize(glm::vec3(0.3f, -0.7f, 0.2f)));
  directions.push_back(glm::normalize(glm::vec3(-0.9f, 0.1f, 0.45f)));
  double mean = 0.0;
  for (const glm::vec3& w : directions) {
    double projected = 0.0;
    for (const Emitter& e : *emitters_) projected += e.area * std::max(0.0f, glm::dot(e.normal, w));
    EXPECT_NEAR(projected, disk, 0.05 * disk) << "direction " << w.x << " " << w.y << " " << w.z;
    mean += projected / static_cast<double>(directions.size());
  }
  EXPECT_NEAR(mean, disk, 0.03 * disk);
}

// E/L for a receiver facing the centre of a sphere of radius r at distance d
// (the whole sphere above its horizon): pi r^2 / d^2.
double sphereFactor(double d) {
  return kPi * kSphereRadius * kSphereRadius / (d * d);
}

TEST_F(SphereLamp, IrradianceFarFromTheLamp) {
  const double d = 1.2;
  const std::vector<glm::vec3> directions = {glm::vec3(0, -1, 0),
                                             glm::vec3(0, 1, 0),
                                             glm::vec3(1, 0, 0),
                                             glm::vec3(0, 0, 1),
                                             glm::normalize(glm::vec3(1, -1, 1)),
                                             glm::normalize(glm::vec3(-0.3f, -0.8f, 0.5f))};
  for (const glm::vec3& w : directions) {
    const glm::vec3 p = kSphereCenter + static_cast<float>(d) * w;
    EXPECT_NEAR(sumAt(p, -w), sphereFactor(d), 0.02 * sphereFactor(d))
        << "from " << w.x << " " << w.y << " " << w.z;
  }
}

TEST_F(SphereLamp, IrradianceNearTheLamp) {
  const double d = 0.2;  // 2.5 radii from the centre
  const std::vector<glm::vec3> directions = {glm::vec3(0, -1, 0),
                                             glm::vec3(0, 1, 0),
                                             glm::vec3(1, 0, 0),
                                             glm::vec3(0, 0, -1),
                                             glm::normalize(glm::vec3(1, -1, 1)),
                                             glm::normalize(glm::vec3(-0.3f, -0.8f, 0.5f))};
  for (const glm::vec3& w : directions) {
    const glm::vec3 p = kSphereCenter + static_cast<float>(d) * w;
    EXPECT_NEAR(sumAt(p, -w), sphereFactor(d), 0.05 * sphereFactor(d))
        << "from " << w.x << " " << w.y << " " << w.z;
  }
}

TEST_F(SphereLamp, NoNanOnTheLamp) {
  // Receivers on a vertex, at a cluster centre and at the sphere's centre.
  std::vector<glm::vec3> points = {scene_->vertices[0].position, scene_->vertices[4000].position,
                                   kSphereCenter};
  for (const Emitter& e : *emitters_) points.push_back(e.v0);
  for (const glm::vec3& p : points) {
    for (const glm::vec3& n :
         {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::normalize(p - kSphereCenter + 1e-3f)}) {
      const double f = sumAt(p, n);
      ASSERT_TRUE(std::isfinite(f)) << p.x << " " << p.y << " " << p.z;
      EXPECT_GE(f, 0.0);
    }
  }
}

TEST(Emitters, SmallEmittersStayExactTriangles) {
  Scene s;
  s.path = "panel";
  const glm::vec3 n(0.0f, -1.0f, 0.0f);
  for (const glm::vec3& p : {glm::vec3(-0.3f, 1.99f, -0.3f), glm::vec3(0.3f, 1.99f, -0.3f),
                             glm::vec3(0.3f, 1.99f, 0.3f), glm::vec3(-0.3f, 1.99f, 0.3f)})
    s.vertices.push_back(Vertex{p, n, glm::vec2(0.0f)});
  s.indices = {0, 1, 2, 0, 2, 3};
  Material m;
  m.emission = glm::vec3(15.0f);
  s.materials.push_back(m);
  Material wall;  // not emissive: ignored
  s.materials.push_back(wall);
  Draw d;
  d.indexCount = 6;
  s.draws.push_back(d);
  d.material = 1;
  s.draws.push_back(d);
  const std::vector<Emitter> emitters = buildEmitters(s);
  ASSERT_EQ(emitters.size(), 2u);
  double area = 0.0;
  for (const Emitter& e : emitters) {
    EXPECT_EQ(e.kind, Emitter::Kind::kTriangle);
    EXPECT_EQ(e.radiance, glm::vec3(15.0f));
    EXPECT_NEAR(glm::dot(e.normal, n), 1.0f, 1e-6f);  // winding as in the mesh
    area += e.area;
  }
  EXPECT_NEAR(area, 0.36, 1e-6);
  // Straight below the panel's centre, facing up.
  const double expected = kPi * 4.0 * cornerFormFactor(0.3 / 1.99, 0.3 / 1.99);
  EXPECT_NEAR(factor(emitters, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f)), expected,
              1e-4 * expected);
}

// --- (e) a primitive of lamps far apart ------------------------------------------------

// Four small sphere lamps (radius 5 cm, 16 x 8 facets each: 896 triangles in all)
// in a row 3-4 m apart, in ONE primitive, as a file that merges its lamps into one
// mesh has them. Every triangle fits among the emitters, so each stays exact:
// clusters made over the whole primitive's bounds mixed facets of lamps metres
// apart into discs where no lamp is.
TEST(Emitters, LampsOfOnePrimitiveStayExactWhenTheyFit) {
  constexpr float r = 0.05f;
  const glm::vec3 centres[4] = {{0, 2, 0}, {3, 2, 0}, {7, 2, 0}, {10, 2, 0}};
  Scene s;
  s.path = "four_lamps";
  const int segments = 16, rings = 8;
  for (const glm::vec3& c : centres) {
    const auto base = static_cast<uint32_t>(s.vertices.size());
    for (int i = 0; i <= rings; ++i)
      for (int j = 0; j <= segments; ++j) {
        const double theta = kPi * i / rings, phi = 2.0 * kPi * j / segments;
        const glm::vec3 n(static_cast<float>(std::sin(theta) * std::cos(phi)),
                          static_cast<float>(std::cos(theta)),
                          static_cast<float>(std::sin(theta) * std::sin(phi)));
        s.vertices.push_back(Vertex{c + r * n, n, glm::vec2(0.0f)});
      }
    auto at = [&](int i, int j) { return base + static_cast<uint32_t>(i * (segments + 1) + j); };
    for (int i = 0; i < rings; ++i)
      for (int j = 0; j < segments; ++j) {
        if (i != 0) s.indices.insert(s.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
        if (i != rings - 1)
          s.indices.insert(s.indices.end(), {at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
      }
  }
  Material m;
  m.emission = glm::vec3(50.0f);
  s.materials.push_back(m);
  Draw d;
  d.indexCount = static_cast<uint32_t>(s.indices.size());
  s.draws.push_back(d);
  ASSERT_EQ(s.triangleCount(), 896u);
  const std::vector<Emitter> emitters = buildEmitters(s);
  EXPECT_EQ(emitters.size(), 896u);
  for (const Emitter& e : emitters) EXPECT_EQ(e.kind, Emitter::Kind::kTriangle);
  // 40 cm below each lamp, facing it: a sphere's irradiance per unit radiance,
  // pi (r / d)^2, within the facets' shortfall (the 16 x 8 sphere has 2.5% less
  // area than the sphere); the other lamps, 3 m away and low over the horizon, add
  // 0.5% at most.
  for (const glm::vec3& c : centres) {
    const glm::vec3 p = c - glm::vec3(0.0f, 0.4f, 0.0f);
    const double expected = kPi * (r / 0.4) * (r / 0.4);
    EXPECT_NEAR(factor(emitters, p, glm::vec3(0.0f, 1.0f, 0.0f)), expected, 0.04 * expected);
  }
  // More triangles than the emitters hold: merged into clusters again.
  const std::vector<Emitter> few = buildEmitters(s, EmitterOptions{32, 800});
  EXPECT_LT(few.size(), 800u);
  EXPECT_EQ(few.front().kind, Emitter::Kind::kCluster);
}

// A model whose only emission is a glowing detail is lit as one with none: the default
// light is added where the emitters are too faint to light the scene
// (Scene::kLitByEmitters), and not where they are its lamps, at any scale.
// A 2 m box (24 m^2) with a 10 x 10 cm double-sided panel of radiance L beside it
// sends pi L x 0.02 m^2 over 24.01 m^2: 0.0026 L.
TEST(DefaultLight, AddedWhereTheEmittersAreTooFaintToLightTheScene) {
  auto make = [](float radiance, float scale) {
    test::SceneBuilder b;
    const glm::mat4 s = glm::scale(glm::mat4(1.0f), glm::vec3(scale));
    b.addBox(glm::vec3(-1.0f), glm::vec3(1.0f), b.addMaterial(glm::vec3(0.5f)), s);
    const int lamp = b.addMaterial(glm::vec3(0.5f), glm::vec3(radiance));
    b.addTriangles({{1.5f, 0.0f, 0.0f},
                    {1.6f, 0.0f, 0.0f},
                    {1.6f, 0.1f, 0.0f},
                    {1.5f, 0.0f, 0.0f},
                    {1.6f, 0.1f, 0.0f},
                    {1.5f, 0.1f, 0.0f}},
                   lamp, s);
    Scene scene = b.finish();
    scene.addDefaultLightIfUnlit();
    return scene;
  };
  for (float scale : {0.001f, 1.0f, 1000.0f}) {
    const Scene faint = make(1.0f, scale);  // a glowing label
    EXPECT_NEAR(faint.emittedLightPerArea(), kPi * 0.02 / 24.01, 1e-5) << scale;
    EXPECT_TRUE(faint.defaultLight) << scale;
    ASSERT_EQ(faint.lights.size(), 1u);
    EXPECT_EQ(faint.lights[0].type, LightType::kDirectional);
    const Scene lit = make(100.0f, scale);  // a lamp: 0.26
    EXPECT_FALSE(lit.defaultLight) << scale;
    EXPECT_TRUE(lit.lights.empty()) << scale;
  }
}

}  // namespace
}  // namespace voxgi::scene
