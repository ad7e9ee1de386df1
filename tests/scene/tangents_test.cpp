// MikkTSpace tangent generation (scene/tangents.h) on cases with known answers.
#include "scene/tangents.h"

#include <gtest/gtest.h>

#include <cmath>

namespace voxgi::scene {
namespace {

void expectNear(const glm::vec4& a, const glm::vec4& b, float tol = 1e-5f) {
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(a[k], b[k], tol) << "component " << k;
}

// A unit quad in z = 0 facing +z, u along x and v along y.
struct Quad {
  std::vector<glm::vec3> p{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<glm::vec3> n{4, glm::vec3(0, 0, 1)};
  std::vector<glm::vec2> uv{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<uint32_t> idx{0, 1, 2, 0, 2, 3};
};

TEST(Tangents, QuadAlongU) {
  Quad q;
  for (const glm::vec4& t : generateTangents(q.p, q.n, q.uv, q.idx))
    expectNear(t, glm::vec4(1, 0, 0, 1));
}

TEST(Tangents, RotatedUvs) {
  // u along y, v along -x: tangent +y; (n, t, dP/dv) = (z, y, -x) is right-handed.
  Quad q;
  q.uv = {{0, 0}, {0, -1}, {1, -1}, {1, 0}};
  for (const glm::vec4& t : generateTangents(q.p, q.n, q.uv, q.idx))
    expectNear(t, glm::vec4(0, 1, 0, 1));
}

TEST(Tangents, MirroredUvsFlipHandedness) {
  Quad q;
  for (glm::vec2& uv : q.uv) uv.x = 1.0f - uv.x;
  for (const glm::vec4& t : generateTangents(q.p, q.n, q.uv, q.idx))
    expectNear(t, glm::vec4(-1, 0, 0, -1));
  // Swapping the winding changes nothing: the frame follows the normal and the UVs.
  Quad r;
  r.idx = {0, 2, 1, 0, 3, 2};
  for (const glm::vec4& t : generateTangents(r.p, r.n, r.uv, r.idx))
    expectNear(t, glm::vec4(1, 0, 0, 1));
}

TEST(Tangents, OrthogonalToTheNormal) {
  // Tilted vertex normals: the tangent is projected into each normal's plane.
  Quad q;
  const glm::vec3 tilted = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f));
  q.n = {tilted, tilted, tilted, tilted};
  for (const glm::vec4& t : generateTangents(q.p, q.n, q.uv, q.idx)) {
    EXPECT_NEAR(glm::dot(glm::vec3(t), tilted), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
    EXPECT_EQ(t.w, 1.0f);
    EXPECT_GT(t.x, 0.9f);
  }
}

TEST(Tangents, SplitVerticesShareOneTangent) {
  // Two triangles of a fold (the second tilted up about x = 1) meeting at split
  // vertices with equal position, normal and UV: both copies get the same tangent,
  // the angle-weighted mean of the faces'.
  const glm::vec3 n(0, 0, 1);
  std::vector<glm::vec3> p{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 0, 0}, {2, 0, 0.5f}, {1, 1, 0}};
  std::vector<glm::vec3> nn(6, n);
  std::vector<glm::vec2> uv{{0, 0}, {1, 0}, {1, 1}, {1, 0}, {2, 0}, {1, 1}};
  std::vector<uint32_t> idx{0, 1, 2, 3, 4, 5};
  const auto t = generateTangents(p, nn, uv, idx);
  expectNear(t[1], t[3]);
  expectNear(t[2], t[5]);
  for (const glm::vec4& x : t) EXPECT_NEAR(glm::length(glm::vec3(x)), 1.0f, 1e-5f);
}

TEST(Tangents, DegenerateUvsGetAPerpendicular) {
  Quad q;
  q.uv.assign(4, glm::vec2(0.5f));
  for (const glm::vec4& t : generateTangents(q.p, q.n, q.uv, q.idx)) {
    EXPECT_NEAR(glm::dot(glm::vec3(t), q.n[0]), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
    EXPECT_FALSE(std::isnan(t.x));
  }
}

}  // namespace
}  // namespace voxgi::scene
